//! The paper's linear map t = M w (Hlawitschka et al.) from an SH series of band L to the
//! symmetric tensor of order n = max(L, 2) that equals it on the unit sphere.
//!
//! M is built in closed form, column by column: each basis function
//! factor * Q_l^|m|(z) * Re/Im (x+iy)^|m| becomes a homogeneous polynomial of degree l by
//! running the Legendre recurrences of `legendre` on polynomials, where the three-term
//! step multiplies Q_(l-2) by r^2 = x^2 + y^2 + z^2 so that both terms have degree l - m
//! (r^2 = 1 on the sphere). Multiplying by (r^2)^((n-l)/2) lifts it to degree n, and
//! dividing each monomial coefficient by its multiplicity gives the tensor entries
//! (scene format, Eq. 5 weights). A homogeneous polynomial that vanishes on the sphere
//! is zero, so this tensor is the unique one; a least-squares fit would find the same M
//! but lose digits to the poor conditioning of the monomial basis.
//!
//! Band 0 maps to order 2 (w Y_0^0 |u|^2), since order 0 is not renderable.
use std::sync::Arc;

use super::basis::{Part, basis_term};
use super::cache::{BasisKey, Cache, cached};
use super::legendre::{first_step, q00, sectoral_ratio, three_term};
use super::{check_band, check_coefficients, sh_count, sh_index};
use crate::Result;
use crate::glyph::homogeneous::Homogeneous;
use crate::glyph::monomials::symmetric_count;
use crate::glyph::sh::ShBasis;

/// M of one (band, basis, legacy): `symmetric_count(order)` rows by `sh_count(band)`
/// columns, row-major. Row k is tensor coefficient k in the scene format's order.
#[derive(Clone, Debug, PartialEq)]
pub struct ShToTensor {
    /// The highest SH band L.
    pub band: u32,
    /// The tensor order, max(L, 2).
    pub order: u32,
    /// M's entries, row-major.
    pub matrix: Vec<f64>,
    /// M's non-zero entries, row by row as (column, value): most of M is zero (a band's
    /// (l, m) reaches only the monomials of its parities in x and y), and `apply` skips
    /// those, with the same sum as the dense product (the zeros are exact).
    nonzeros: Vec<(u16, f64)>,
    /// Where each row's entries start in `nonzeros`, and one past the last row's end.
    row_starts: Vec<u32>,
}

impl ShToTensor {
    /// Number of tensor coefficients (rows).
    pub fn rows(&self) -> usize {
        symmetric_count(self.order)
    }

    /// Number of SH coefficients (columns).
    pub fn cols(&self) -> usize {
        sh_count(self.band)
    }

    /// t = M w. Missing coefficients count as zero and extra ones are ignored; use
    /// [`sh_to_tensor`] for a checked call.
    pub fn apply(&self, coeffs: &[f64]) -> Vec<f64> {
        self.row_starts
            .windows(2)
            .map(|span| {
                self.nonzeros[span[0] as usize..span[1] as usize]
                    .iter()
                    .map(|&(j, m)| m * coeffs.get(j as usize).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect()
    }
}

static CACHE: Cache<BasisKey, ShToTensor> = Cache::new();

/// M for (band, basis, legacy), built once per process and shared.
pub fn sh_to_tensor_matrix(band: u32, basis: ShBasis, legacy: bool) -> Result<Arc<ShToTensor>> {
    check_band(band)?;
    cached(&CACHE, BasisKey::new(band, basis, legacy), || {
        Ok(build(band, basis, legacy))
    })
}

/// The symmetric tensor (order, unique coefficients in scene order) equal to the SH
/// series on the unit sphere.
pub fn sh_to_tensor(
    band: u32,
    basis: ShBasis,
    legacy: bool,
    coeffs: &[f64],
) -> Result<(u32, Vec<f64>)> {
    check_coefficients(band, coeffs)?;
    let m = sh_to_tensor_matrix(band, basis, legacy)?;
    Ok((m.order, m.apply(coeffs)))
}

fn build(band: u32, basis: ShBasis, legacy: bool) -> ShToTensor {
    let order = band.max(2);
    let cols = sh_count(band);
    let mut matrix = vec![0.0; symmetric_count(order) * cols];
    let azimuthal = azimuthal_polynomials(band);
    for (k, (re, im)) in (0..=band).zip(&azimuthal) {
        for (l, q) in (k..=band).zip(q_polynomials(band, k)) {
            if !l.is_multiple_of(2) {
                continue;
            }
            let signed = if k == 0 {
                vec![0]
            } else {
                vec![-(k as i32), k as i32]
            };
            for m in signed {
                let (part, factor) = basis_term(basis, legacy, m);
                let trig = if part == Part::Re { re } else { im };
                let column = q
                    .mul(trig)
                    .scaled(factor)
                    .raised_by((order - l) / 2)
                    .to_symmetric_tensor();
                let j = sh_index(l, m);
                for (row, value) in column.into_iter().enumerate() {
                    matrix[row * cols + j] = value;
                }
            }
        }
    }
    let mut nonzeros = Vec::new();
    let mut row_starts = vec![0];
    for row in matrix.chunks(cols) {
        nonzeros.extend(
            (0u16..)
                .zip(row)
                .filter(|(_, m)| **m != 0.0)
                .map(|(j, m)| (j, *m)),
        );
        row_starts.push(nonzeros.len() as u32);
    }
    ShToTensor {
        band,
        order,
        matrix,
        nonzeros,
        row_starts,
    }
}

/// (Re, Im) of (x + iy)^k as homogeneous polynomials of degree k, for k = 0..=band.
fn azimuthal_polynomials(band: u32) -> Vec<(Homogeneous, Homogeneous)> {
    let x = Homogeneous::linear([1.0, 0.0, 0.0]);
    let y = Homogeneous::linear([0.0, 1.0, 0.0]);
    let mut out = Vec::with_capacity(band as usize + 1);
    let (mut re, mut im) = (Homogeneous::constant(1.0), Homogeneous::constant(0.0));
    for _ in 0..=band {
        let next_re = re.mul(&x).combine(1.0, &im.mul(&y), -1.0);
        let next_im = re.mul(&y).combine(1.0, &im.mul(&x), 1.0);
        out.push((re, im));
        (re, im) = (next_re, next_im);
    }
    out
}

/// Q_l^k as homogeneous polynomials of degree l - k, for l = k..=band.
fn q_polynomials(band: u32, k: u32) -> Vec<Homogeneous> {
    let z = Homogeneous::linear([0.0, 0.0, 1.0]);
    let r2 = Homogeneous::radius_squared();
    let sectoral = (1..=k).fold(q00(), |q, m| q * sectoral_ratio(m));
    let mut prev = Homogeneous::constant(sectoral);
    let mut out = vec![prev.clone()];
    if k == band {
        return out;
    }
    let mut cur = z.scaled(first_step(k) * sectoral);
    out.push(cur.clone());
    for l in k + 2..=band {
        let (a, b) = three_term(l, k);
        let next = z.mul(&cur).combine(a, &r2.mul(&prev), -a * b);
        out.push(next.clone());
        (prev, cur) = (cur, next);
    }
    out
}
