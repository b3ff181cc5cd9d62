//! Elastic stiffness tensors C_ijkl from 6 x 6 matrices in Voigt notation, as order-4
//! glyphs.
//!
//! Hooke's law sigma_ij = C_ijkl eps_kl; C has the minor symmetries C_ijkl = C_jikl =
//! C_ijlk and the major symmetry C_ijkl = C_klij, which leave 21 independent entries,
//! written as a symmetric 6 x 6 matrix V_pq with p = voigt(i, j), q = voigt(k, l) (Nye,
//! "Physical Properties of Crystals", 1957, ch. VIII; no factors of 2 on the stiffness
//! side). The standard shear order is 4 = 23, 5 = 13, 6 = 12; some codes write
//! 4 = 12, 5 = 13, 6 = 23 ([`ShearOrder::Reversed`]). Matrices are stored here in the
//! standard order whatever order the file used.
//!
//! The glyph is f(u) = C_ijkl u_i u_j u_k u_l (for a unit u, the longitudinal stiffness
//! u . (C : (u (x) u)) . u), drawn either from all 81 entries (non-symmetric layout, row
//! major with l fastest) or from the fully symmetric part, the average of C over all 24
//! permutations of (i, j, k, l): the same quartic form, in 15 unique coefficients. They
//! differ as tensors (sym(C)_1122 = (C12 + 2 C44) / 3, not C12) but not as glyphs.
//!
//! `io::stiffness` reads the matrix from CSV or JSON files.
use glam::DMat3;

use crate::glyph::monomials::{
    monomial_index, monomials, multiplicity, nonsymmetric_entry_monomial,
};
use crate::{Error, Result};

/// Entries that differ from their transpose by more than this fraction of the largest
/// entry make the matrix "not symmetric". Tables typed from papers are exactly
/// symmetric; 1e-6 still admits matrices computed in float32.
pub const SYMMETRY_TOLERANCE: f64 = 1e-6;

/// Which index pairs the Voigt rows 4, 5, 6 stand for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShearOrder {
    /// 4 = 23, 5 = 13, 6 = 12 (standard Voigt).
    #[default]
    Standard,
    /// 4 = 12, 5 = 13, 6 = 23.
    Reversed,
}

impl ShearOrder {
    /// "23,13,12" or "12,13,23" (spaces allowed).
    pub fn parse(text: &str) -> Option<Self> {
        let compact: String = text.chars().filter(|c| !c.is_whitespace()).collect();
        match compact.as_str() {
            "23,13,12" => Some(ShearOrder::Standard),
            "12,13,23" => Some(ShearOrder::Reversed),
            _ => None,
        }
    }

    /// The order as [`ShearOrder::parse`] reads it, without spaces.
    pub fn name(self) -> &'static str {
        match self {
            ShearOrder::Standard => "23,13,12",
            ShearOrder::Reversed => "12,13,23",
        }
    }

    /// The (i, j) pair (0-based) of each Voigt row.
    fn pairs(self) -> [(usize, usize); 6] {
        let normal = [(0, 0), (1, 1), (2, 2)];
        let shear = match self {
            ShearOrder::Standard => [(1, 2), (0, 2), (0, 1)],
            ShearOrder::Reversed => [(0, 1), (0, 2), (1, 2)],
        };
        [
            normal[0], normal[1], normal[2], shear[0], shear[1], shear[2],
        ]
    }
}

/// Standard Voigt row (0-based) of the index pair (i, j): 11 22 33 23 13 12.
pub fn voigt_index(i: usize, j: usize) -> usize {
    if i == j { i } else { 6 - i - j }
}

/// A symmetric 6 x 6 stiffness matrix in the standard shear order.
#[derive(Clone, Debug, PartialEq)]
pub struct VoigtStiffness {
    /// C_pq, row p and column q in the Voigt order 11 22 33 23 13 12.
    pub matrix: [[f64; 6]; 6],
}

impl VoigtStiffness {
    /// A cubic crystal in its cube axes: C11 on the normal diagonal, C12 off it, C44 on
    /// the shear diagonal.
    pub fn cubic(c11: f64, c12: f64, c44: f64) -> Self {
        let mut matrix = [[0.0; 6]; 6];
        for (p, row) in matrix.iter_mut().enumerate() {
            for (q, v) in row.iter_mut().enumerate() {
                *v = match (p < 3, q < 3) {
                    (true, true) if p == q => c11,
                    (true, true) => c12,
                    (false, false) if p == q => c44,
                    _ => 0.0,
                };
            }
        }
        Self { matrix }
    }

    /// Checks a matrix written in `order` (finite, symmetric to SYMMETRY_TOLERANCE) and
    /// brings it to the standard order; `source` names it in errors. The stored matrix
    /// is the exact average of the matrix and its transpose.
    pub fn from_matrix(matrix: [[f64; 6]; 6], order: ShearOrder, source: &str) -> Result<Self> {
        let field = |p: usize, q: usize| format!("C{}{}", p + 1, q + 1);
        for (p, q) in (0..6).flat_map(|p| (0..6).map(move |q| (p, q))) {
            if !matrix[p][q].is_finite() {
                let message = format!("{} is not a finite number", matrix[p][q]);
                return Err(Error::input(source, field(p, q), message));
            }
        }
        let largest = matrix.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for (p, q) in (0..6).flat_map(|p| (p + 1..6).map(move |q| (p, q))) {
            let (v, w) = (matrix[p][q], matrix[q][p]);
            if (v - w).abs() > SYMMETRY_TOLERANCE * largest {
                let message = format!(
                    "{v}, but {} is {w}: a stiffness matrix is symmetric (tolerance {SYMMETRY_TOLERANCE} of the largest entry)",
                    field(q, p)
                );
                return Err(Error::input(source, field(p, q), message));
            }
        }
        let pairs = order.pairs();
        let mut standard = [[0.0; 6]; 6];
        for p in 0..6 {
            for q in 0..6 {
                let (sp, sq) = (
                    voigt_index(pairs[p].0, pairs[p].1),
                    voigt_index(pairs[q].0, pairs[q].1),
                );
                standard[sp][sq] = 0.5 * (matrix[p][q] + matrix[q][p]);
            }
        }
        Ok(Self { matrix: standard })
    }

    /// The matrix written in `order`.
    pub fn in_order(&self, order: ShearOrder) -> [[f64; 6]; 6] {
        let pairs = order.pairs();
        let mut out = [[0.0; 6]; 6];
        for p in 0..6 {
            for q in 0..6 {
                out[p][q] = self.matrix[voigt_index(pairs[p].0, pairs[p].1)]
                    [voigt_index(pairs[q].0, pairs[q].1)];
            }
        }
        out
    }

    /// All 81 entries C_ijkl, row major (i most significant, l fastest).
    pub fn full_tensor(&self) -> Vec<f64> {
        (0..81)
            .map(|flat| {
                let [i, j, k, l] = indices(flat);
                self.matrix[voigt_index(i, j)][voigt_index(k, l)]
            })
            .collect()
    }

    /// All 81 entries of the crystal turned by `rotation`: C'_ijkl = R_ia R_jb R_kc R_ld
    /// C_abcd ([`crate::glyph::rotate`]).
    pub fn rotated(&self, rotation: DMat3) -> Vec<f64> {
        crate::glyph::rotate::turn_each_index(4, &self.full_tensor(), rotation)
    }

    /// The 15 unique coefficients of the fully symmetric part, in the scene order.
    pub fn symmetric_part(&self) -> Vec<f64> {
        fully_symmetric_part(4, &self.full_tensor())
    }
}

/// (i, j, k, l) of a row-major flat index of an order-4 tensor.
fn indices(flat: usize) -> [usize; 4] {
    [flat / 27, flat / 9 % 3, flat / 3 % 3, flat % 3]
}

/// Unique coefficients (scene order) of the average of a full order-n tensor over all
/// permutations of its indices. Each sorted index tuple's entry is the mean of the
/// entries at its distinct orderings (every ordering occurs equally often among the n!
/// permutations), i.e. their sum divided by the multiplicity.
pub(crate) fn fully_symmetric_part(order: u32, full: &[f64]) -> Vec<f64> {
    let mut sums = vec![0.0; monomials(order).len()];
    for (flat, value) in full.iter().enumerate() {
        sums[monomial_index(order, nonsymmetric_entry_monomial(order, flat))] += value;
    }
    monomials(order)
        .into_iter()
        .zip(sums)
        .map(|(m, sum)| sum / multiplicity(m) as f64)
        .collect()
}

#[cfg(test)]
mod tests;
