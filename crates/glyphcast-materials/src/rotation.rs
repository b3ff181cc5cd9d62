//! Crystal orientations: rotation matrices, Bunge Euler angles, and rotated tensors.

use crate::error::{Error, RotationDefect};
use crate::stiffness::Stiffness;
use crate::voigt::{Kind, Tensor4, VOIGT_PAIRS, Voigt, from_tensor, to_tensor};

/// Tolerance of the rotation check: `|g gᵀ - I|` entrywise and `|det g - 1|`.
pub const ROTATION_TOLERANCE: f64 = 1e-6;

/// A proper rotation `g` mapping sample coordinates to crystal coordinates:
/// `x_crystal = g · x_sample` (the texture-analysis convention of MTEX and EBSD
/// software).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotation {
    g: [[f64; 3]; 3],
}

impl Rotation {
    /// The identity (sample and crystal frames coincide).
    pub const IDENTITY: Rotation = Rotation {
        g: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// Accepts `g` (rows `g[i]`) if it is orthonormal with determinant +1 within
    /// 1e-6; the error says which entry or the determinant is off.
    pub fn from_matrix(g: [[f64; 3]; 3]) -> Result<Self, Error> {
        for (i, row) in g.iter().enumerate() {
            if let Some(j) = row.iter().position(|x| !x.is_finite()) {
                return Err(RotationDefect::NonFinite {
                    row: i + 1,
                    column: j + 1,
                }
                .into());
            }
        }
        for i in 0..3 {
            for j in 0..3 {
                let product: f64 = (0..3).map(|k| g[i][k] * g[j][k]).sum();
                let deviation = product - if i == j { 1.0 } else { 0.0 };
                if deviation.abs() > ROTATION_TOLERANCE {
                    return Err(RotationDefect::NotOrthonormal {
                        row: i + 1,
                        column: j + 1,
                        deviation,
                    }
                    .into());
                }
            }
        }
        let determinant = determinant(&g);
        if (determinant - 1.0).abs() > ROTATION_TOLERANCE {
            return Err(RotationDefect::NotProper { determinant }.into());
        }
        Ok(Self { g })
    }

    /// The orientation of Bunge Euler angles `(φ1, Φ, φ2)` in degrees:
    /// `g = Rz(φ2) · Rx(Φ) · Rz(φ1)` with the passive matrices
    /// `Rz(φ) = [[cos φ, sin φ, 0], [-sin φ, cos φ, 0], [0, 0, 1]]` and
    /// `Rx(Φ) = [[1, 0, 0], [0, cos Φ, sin Φ], [0, -sin Φ, cos Φ]]`.
    pub fn from_bunge_degrees(phi1: f64, big_phi: f64, phi2: f64) -> Result<Self, Error> {
        for (value, angle) in [(phi1, "phi1"), (big_phi, "Phi"), (phi2, "phi2")] {
            if !value.is_finite() {
                return Err(Error::NonFiniteAngle { angle });
            }
        }
        let g = multiply(
            &multiply(
                &passive_z(phi2.to_radians()),
                &passive_x(big_phi.to_radians()),
            ),
            &passive_z(phi1.to_radians()),
        );
        Ok(Self { g })
    }

    /// The matrix `g` (rows `g[i]`).
    pub fn matrix(&self) -> [[f64; 3]; 3] {
        self.g
    }

    /// `g · u`: a sample-frame direction in crystal coordinates.
    pub fn to_crystal(&self, u: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| self.g[i][j] * u[j]).sum())
    }

    /// `gᵀ · u`: a crystal-frame direction in sample coordinates.
    pub fn to_sample(&self, u: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|j| self.g[j][i] * u[j]).sum())
    }
}

/// The passive rotation about z by `angle` radians.
fn passive_z(angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// The passive rotation about x by `angle` radians.
fn passive_x(angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]]
}

/// The matrix product `a · b`.
fn multiply(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// The determinant of a 3x3 matrix.
fn determinant(a: &[[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// The crystal-frame tensor `t` in the sample frame: `t'_ijkl = g_mi g_nj g_ok g_pl t_mnop`.
pub fn rotate_tensor(t: &Tensor4, g: &Rotation) -> Tensor4 {
    let g = &g.g;
    // One index at a time: four passes of 3^5 products instead of one of 3^8.
    let mut current = *t;
    for slot in 0..4 {
        let mut next = [[[[0.0; 3]; 3]; 3]; 3];
        for (flat, entry) in next.iter_mut().flatten().flatten().flatten().enumerate() {
            let index = [flat / 27, flat / 9 % 3, flat / 3 % 3, flat % 3];
            *entry = (0..3)
                .map(|m| {
                    let mut source = index;
                    source[slot] = m;
                    g[m][index[slot]] * current[source[0]][source[1]][source[2]][source[3]]
                })
                .sum();
        }
        current = next;
    }
    current
}

/// The crystal-frame Voigt stiffness `c` in the sample frame (through the
/// fourth-order tensor: `C'_ijkl = g_mi g_nj g_ok g_pl C_mnop`).
pub fn rotate(c: &Voigt, g: &Rotation) -> Voigt {
    rotate_voigt(c, g, Kind::Stiffness)
}

/// A crystal-frame Voigt matrix of either kind in the sample frame.
fn rotate_voigt(voigt: &Voigt, g: &Rotation, kind: Kind) -> Voigt {
    from_tensor(&rotate_tensor(&to_tensor(voigt, kind), g), kind)
}

/// The 6x6 Bond matrix `M` of `g`: `rotate(c, g) = M · c · Mᵀ` for a Voigt stiffness.
///
/// With `a = gᵀ` (so `C'_ijkl = a_im a_jn a_ko a_lp C_mnop`), entry `(I, J)` for
/// Voigt pairs `I = (i, j)`, `J = (m, n)` is `a_im a_jn` plus, for a shear `J`, the
/// swapped term `a_in a_jm`.
pub fn bond_matrix(g: &Rotation) -> Voigt {
    let a = |i: usize, m: usize| g.g[m][i];
    std::array::from_fn(|row| {
        let (i, j) = VOIGT_PAIRS[row];
        std::array::from_fn(|column| {
            let (m, n) = VOIGT_PAIRS[column];
            let direct = a(i, m) * a(j, n);
            if m == n {
                direct
            } else {
                direct + a(i, n) * a(j, m)
            }
        })
    })
}

impl Stiffness {
    /// This crystal-frame stiffness seen in the sample frame of orientation `g`: the
    /// stiffness and compliance tensors are both rotated, so no inversion is redone.
    /// `rotated(g).young(u) == young(g · u)`.
    pub fn rotated(&self, g: &Rotation) -> Stiffness {
        Stiffness::from_parts(
            rotate_voigt(self.voigt(), g, Kind::Stiffness),
            rotate_voigt(self.compliance(), g, Kind::Compliance),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals() {
        let mut g = Rotation::IDENTITY.matrix();
        g[1][2] = f64::NAN;
        assert_eq!(
            Rotation::from_matrix(g),
            Err(Error::NotRotation(RotationDefect::NonFinite {
                row: 2,
                column: 3
            }))
        );
        let mut g = Rotation::IDENTITY.matrix();
        g[0][0] = 1.001;
        assert!(matches!(
            Rotation::from_matrix(g),
            Err(Error::NotRotation(RotationDefect::NotOrthonormal {
                row: 1,
                column: 1,
                ..
            }))
        ));
        let reflection = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]];
        let error = Rotation::from_matrix(reflection).unwrap_err();
        assert_eq!(
            error,
            Error::NotRotation(RotationDefect::NotProper { determinant: -1.0 })
        );
        assert!(error.to_string().contains("determinant"), "{error}");
        assert_eq!(
            Rotation::from_bunge_degrees(0.0, f64::NAN, 0.0),
            Err(Error::NonFiniteAngle { angle: "Phi" })
        );
        // Within the tolerance: accepted.
        let mut g = Rotation::IDENTITY.matrix();
        g[0][1] = 1e-7;
        assert!(Rotation::from_matrix(g).is_ok());
    }

    /// Bunge's explicit matrix (Bunge, Texture Analysis in Materials Science, eq. 2.5),
    /// entry by entry, against the product of the three passive rotations.
    #[test]
    fn bunge_matches_the_explicit_matrix() {
        let (p1, pp, p2) = (31.0_f64, 47.0_f64, 113.0_f64);
        let g = Rotation::from_bunge_degrees(p1, pp, p2).unwrap().matrix();
        let (s1, c1) = p1.to_radians().sin_cos();
        let (s, c) = pp.to_radians().sin_cos();
        let (s2, c2) = p2.to_radians().sin_cos();
        let expected = [
            [c1 * c2 - s1 * s2 * c, s1 * c2 + c1 * s2 * c, s2 * s],
            [-c1 * s2 - s1 * c2 * c, -s1 * s2 + c1 * c2 * c, c2 * s],
            [s1 * s, -c1 * s, c],
        ];
        for i in 0..3 {
            for j in 0..3 {
                assert!((g[i][j] - expected[i][j]).abs() < 1e-15, "({i},{j})");
            }
        }
        assert!(Rotation::from_matrix(g).is_ok());
    }

    #[test]
    fn to_sample_undoes_to_crystal() {
        let g = Rotation::from_bunge_degrees(10.0, 20.0, 30.0).unwrap();
        let u = [0.3, -0.4, 0.5];
        let back = g.to_sample(g.to_crystal(u));
        for i in 0..3 {
            assert!((back[i] - u[i]).abs() < 1e-15);
        }
    }
}
