//! Voigt notation: the 6x6 matrices and the 3x3x3x3 tensors they stand for.
//!
//! Voigt index `m` (0-based here, `m + 1` in the names `C11`…`C66`) stands for the pair
//! of tensor indices `(0,0), (1,1), (2,2), (1,2), (0,2), (0,1)`, i.e. 11, 22, 33, 23,
//! 13, 12. A stiffness entry is the tensor entry itself, `C_ijkl = C_mn`. A compliance
//! uses engineering shear strains (`S44 = 1/G`), so `s_ijkl = S_mn · w_m · w_n` with
//! `w = 1` for `m < 3` and `w = 1/2` for a shear index.

/// A 6x6 matrix in Voigt notation.
pub type Voigt = [[f64; 6]; 6];

/// A fourth-order tensor on 3D space, indexed `t[i][j][k][l]`.
pub type Tensor4 = [[[[f64; 3]; 3]; 3]; 3];

/// The tensor index pair `(i, j)` of Voigt index `m` (both 0-based).
pub const VOIGT_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// The Voigt index (0-based) of the tensor index pair `(i, j)`, in either order.
pub fn voigt_index(i: usize, j: usize) -> usize {
    match (i.min(j), i.max(j)) {
        (a, b) if a == b => a,
        (1, 2) => 3,
        (0, 2) => 4,
        _ => 5,
    }
}

/// Which kind of quantity a Voigt matrix holds: it decides the shear factors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A stiffness: `C_ijkl = C_mn`.
    Stiffness,
    /// A compliance with engineering shear strains: `s_ijkl = S_mn · w_m · w_n`.
    Compliance,
}

/// The factor `w_m · w_n` between Voigt entry `(m, n)` and its tensor entries.
fn shear_factor(kind: Kind, m: usize, n: usize) -> f64 {
    let weight = |index: usize| if index < 3 { 1.0 } else { 0.5 };
    match kind {
        Kind::Stiffness => 1.0,
        Kind::Compliance => weight(m) * weight(n),
    }
}

/// The fourth-order tensor that the Voigt matrix `voigt` stands for.
///
/// The result has the minor and (for a symmetric `voigt`) major symmetries.
pub fn to_tensor(voigt: &Voigt, kind: Kind) -> Tensor4 {
    let mut tensor = [[[[0.0; 3]; 3]; 3]; 3];
    for (i, plane) in tensor.iter_mut().enumerate() {
        for (j, block) in plane.iter_mut().enumerate() {
            for (k, row) in block.iter_mut().enumerate() {
                for (l, entry) in row.iter_mut().enumerate() {
                    let (m, n) = (voigt_index(i, j), voigt_index(k, l));
                    *entry = voigt[m][n] * shear_factor(kind, m, n);
                }
            }
        }
    }
    tensor
}

/// The Voigt matrix of a tensor with the minor symmetries (the inverse of [`to_tensor`]).
pub fn from_tensor(tensor: &Tensor4, kind: Kind) -> Voigt {
    let mut voigt = [[0.0; 6]; 6];
    for (m, row) in voigt.iter_mut().enumerate() {
        for (n, entry) in row.iter_mut().enumerate() {
            let ((i, j), (k, l)) = (VOIGT_PAIRS[m], VOIGT_PAIRS[n]);
            *entry = tensor[i][j][k][l] / shear_factor(kind, m, n);
        }
    }
    voigt
}

/// `t(a, b, c, d) = Σ t_ijkl a_i b_j c_k d_l`: the tensor as a multilinear form.
pub fn contract(t: &Tensor4, a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let mut sum = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                for l in 0..3 {
                    sum += t[i][j][k][l] * a[i] * b[j] * c[k] * d[l];
                }
            }
        }
    }
    sum
}

/// The 3x3 matrix `M_jl = Σ t_ijkl a_i c_k` (two slots filled, the second and fourth
/// left open): `t(a, v, c, w) = vᵀ M w`.
pub(crate) fn partial_contract_13(t: &Tensor4, a: [f64; 3], c: [f64; 3]) -> [[f64; 3]; 3] {
    let mut m = [[0.0; 3]; 3];
    for (i, plane) in t.iter().enumerate() {
        for (j, block) in plane.iter().enumerate() {
            for (k, row) in block.iter().enumerate() {
                for (l, entry) in row.iter().enumerate() {
                    m[j][l] += entry * a[i] * c[k];
                }
            }
        }
    }
    m
}

/// The 3x3 matrix `M_kl = Σ t_ijkl a_i b_j` (first two slots filled): `t(a, b, v, w) = vᵀ M w`.
pub(crate) fn partial_contract_12(t: &Tensor4, a: [f64; 3], b: [f64; 3]) -> [[f64; 3]; 3] {
    let mut m = [[0.0; 3]; 3];
    for (i, plane) in t.iter().enumerate() {
        for (j, block) in plane.iter().enumerate() {
            for (k, row) in block.iter().enumerate() {
                for (l, entry) in row.iter().enumerate() {
                    m[k][l] += entry * a[i] * b[j];
                }
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_matrix() -> Voigt {
        let mut v = [[0.0; 6]; 6];
        for (m, row) in v.iter_mut().enumerate() {
            for (n, entry) in row.iter_mut().enumerate() {
                *entry = 1.0 + (m * 6 + n) as f64 + (n * 6 + m) as f64;
            }
        }
        v
    }

    #[test]
    fn voigt_pairs_and_index_agree() {
        for (m, &(i, j)) in VOIGT_PAIRS.iter().enumerate() {
            assert_eq!(voigt_index(i, j), m);
            assert_eq!(voigt_index(j, i), m);
        }
    }

    #[test]
    fn tensor_round_trip_and_factors() {
        let v = sample_matrix();
        for kind in [Kind::Stiffness, Kind::Compliance] {
            let back = from_tensor(&to_tensor(&v, kind), kind);
            assert_eq!(back, v);
        }
        // Compliance: s_2323 = S44 / 4, s_1123 = S14 / 2, s_1111 = S11.
        let s = to_tensor(&v, Kind::Compliance);
        assert_eq!(s[1][2][1][2], v[3][3] / 4.0);
        assert_eq!(s[0][0][2][1], v[0][3] / 2.0);
        assert_eq!(s[0][0][0][0], v[0][0]);
        let c = to_tensor(&v, Kind::Stiffness);
        assert_eq!(c[2][1][1][2], v[3][3]);
    }
}
