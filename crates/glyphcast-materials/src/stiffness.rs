//! The validated stiffness, its compliance, and the directional moduli.

use nalgebra::{Matrix6, SymmetricEigen};

use crate::error::Error;
use crate::voigt::{
    Kind, Tensor4, Voigt, contract, partial_contract_12, partial_contract_13, to_tensor,
};

/// Relative tolerance of the symmetry check: `|C_ij - C_ji| ≤ 1e-6 · max|C|`.
pub const SYMMETRY_TOLERANCE: f64 = 1e-6;

/// A stiffness with an eigenvalue below `1e-12 · max|eigenvalue|` counts as singular.
const SINGULAR_TOLERANCE: f64 = 1e-12;

/// Two directions count as perpendicular when `|u·v| ≤ 1e-6` after normalisation.
pub const PERPENDICULAR_TOLERANCE: f64 = 1e-6;

/// How [`Stiffness::with_options`] treats its input.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Options {
    /// Accept a symmetric matrix that is not positive definite (a mechanically
    /// unstable crystal) as long as it is invertible. The directional moduli are then
    /// those of the same formulas and may be negative or infinite.
    pub allow_unstable: bool,
}

/// A validated 6x6 Voigt stiffness matrix with its compliance.
///
/// Built by [`Stiffness::new`] (which refuses an unstable crystal) or
/// [`Stiffness::with_options`]. Values keep the input's units: moduli in the units of
/// `C`, compressibilities in their inverse.
#[derive(Debug, Clone, PartialEq)]
pub struct Stiffness {
    voigt: Voigt,
    compliance: Voigt,
    compliance_tensor: Tensor4,
}

/// The two extremes of a shear modulus or Poisson's ratio over the directions `v`
/// perpendicular to a fixed `u`, with the `v` (unit vectors) that reach them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneExtremes {
    /// The smallest value over unit `v ⊥ u`.
    pub min: f64,
    /// The largest value over unit `v ⊥ u`.
    pub max: f64,
    /// A unit `v ⊥ u` where the value is `min`.
    pub min_v: [f64; 3],
    /// A unit `v ⊥ u` where the value is `max`.
    pub max_v: [f64; 3],
}

impl Stiffness {
    /// Validates `c` and computes its compliance; refuses an unstable crystal.
    ///
    /// Refuses, in this order: a non-finite entry ([`Error::NonFinite`]), a
    /// non-symmetric matrix ([`Error::NotSymmetric`], the first offending pair in row
    /// order), a matrix that is not positive definite ([`Error::Unstable`]). The
    /// matrix kept is the symmetric part `(C + Cᵀ)/2`.
    pub fn new(c: Voigt) -> Result<Self, Error> {
        Self::with_options(c, Options::default())
    }

    /// As [`Stiffness::new`], but with `options.allow_unstable` a matrix that is not
    /// positive definite is accepted if invertible ([`Error::Singular`] otherwise).
    pub fn with_options(c: Voigt, options: Options) -> Result<Self, Error> {
        check_finite(&c)?;
        check_symmetric(&c)?;
        let c = symmetric_part(&c);
        // Work on C / max|C| so that no magnitude of input overflows the eigensolver.
        let scale = largest_entry(&c);
        let scale = if scale > 0.0 { scale } else { 1.0 };
        let matrix = Matrix6::from_fn(|i, j| c[i][j] / scale);
        let eigenvalues = SymmetricEigen::new(matrix).eigenvalues;
        let smallest = eigenvalues.min() * scale;
        if smallest <= 0.0 && !options.allow_unstable {
            return Err(Error::Unstable {
                smallest_eigenvalue: smallest,
            });
        }
        let nearest_zero = eigenvalues
            .iter()
            .copied()
            .fold(f64::INFINITY, |a, e| if e.abs() < a.abs() { e } else { a });
        let singular = Error::Singular {
            smallest_eigenvalue: nearest_zero * scale,
        };
        if nearest_zero.abs() <= SINGULAR_TOLERANCE * eigenvalues.amax() {
            return Err(singular);
        }
        let inverse = matrix.try_inverse().ok_or(singular.clone())?;
        let compliance = symmetric_part(&std::array::from_fn(|i| {
            std::array::from_fn(|j| inverse[(i, j)] / scale)
        }));
        // A compliance beyond float64's range (a stiffness near its smallest numbers).
        if !compliance.iter().flatten().all(|x| x.is_finite()) {
            return Err(singular);
        }
        Ok(Self::from_parts(c, compliance))
    }

    /// A stiffness from a Voigt stiffness and compliance known to be inverses.
    pub(crate) fn from_parts(voigt: Voigt, compliance: Voigt) -> Self {
        Self {
            voigt,
            compliance_tensor: to_tensor(&compliance, Kind::Compliance),
            compliance,
        }
    }

    /// The 6x6 Voigt stiffness `C` (symmetrised).
    pub fn voigt(&self) -> &Voigt {
        &self.voigt
    }

    /// The 6x6 Voigt compliance `S = C⁻¹` (engineering shear convention: `S44 = 1/G`).
    pub fn compliance(&self) -> &Voigt {
        &self.compliance
    }

    /// The compliance tensor `s_ijkl` (`s_ijkl = S_mn · w_m · w_n`, `w = 1` for normal
    /// and `1/2` for shear Voigt indices): the coefficients of the quartic form
    /// `1/E(u) = Σ s_ijkl u_i u_j u_k u_l`.
    pub fn compliance_tensor(&self) -> &Tensor4 {
        &self.compliance_tensor
    }

    /// The stiffness tensor `C_ijkl = C_mn`.
    pub fn stiffness_tensor(&self) -> Tensor4 {
        to_tensor(&self.voigt, Kind::Stiffness)
    }

    /// Young's modulus along `u` (any nonzero length):
    /// `E(u) = 1 / Σ s_ijkl u_i u_j u_k u_l`.
    pub fn young(&self, u: [f64; 3]) -> Result<f64, Error> {
        let u = unit(u, "u")?;
        Ok(1.0 / self.inverse_young_unit(u))
    }

    /// Linear compressibility along `u`: `β(u) = Σ s_ijkk u_i u_j`, in the inverse of
    /// the input's units. Negative: the crystal expands along `u` under hydrostatic
    /// pressure.
    pub fn linear_compressibility(&self, u: [f64; 3]) -> Result<f64, Error> {
        let u = unit(u, "u")?;
        Ok(quadratic(&self.compressibility_matrix(), u))
    }

    /// Shear modulus for shear in plane `u`, direction `v ⊥ u`:
    /// `1/G(u, v) = 4 Σ s_ijkl u_i v_j u_k v_l`.
    pub fn shear(&self, u: [f64; 3], v: [f64; 3]) -> Result<f64, Error> {
        let (u, v) = perpendicular_pair(u, v)?;
        Ok(1.0 / self.inverse_shear_unit(u, v))
    }

    /// Poisson's ratio for tension along `u`, contraction along `v ⊥ u`:
    /// `ν(u, v) = -Σ s_ijkl u_i u_j v_k v_l / Σ s_ijkl u_i u_j u_k u_l`.
    pub fn poisson(&self, u: [f64; 3], v: [f64; 3]) -> Result<f64, Error> {
        let (u, v) = perpendicular_pair(u, v)?;
        Ok(self.poisson_unit(u, v))
    }

    /// The exact smallest and largest shear modulus over unit `v ⊥ u`.
    ///
    /// `1/G` is the quadratic form `4 vᵀ M v`, `M_jl = Σ s_ijkl u_i u_k`; restricted to
    /// the plane ⊥ `u` it is a 2x2 symmetric matrix whose eigenvalues are the extremes
    /// of `1/G` (so `Gmin = 1/λmax`, `Gmax = 1/λmin` for a stable crystal).
    pub fn shear_min_max(&self, u: [f64; 3]) -> Result<PlaneExtremes, Error> {
        let u = unit(u, "u")?;
        Ok(self.shear_min_max_unit(u))
    }

    /// The exact smallest and largest Poisson's ratio over unit `v ⊥ u`.
    ///
    /// The numerator `Σ s_ijkl u_i u_j v_k v_l` is a quadratic form in `v`; its 2x2
    /// restriction to the plane ⊥ `u` has the extremes as eigenvalues.
    pub fn poisson_min_max(&self, u: [f64; 3]) -> Result<PlaneExtremes, Error> {
        let u = unit(u, "u")?;
        Ok(self.poisson_min_max_unit(u))
    }

    /// `1/E(u) = s(u, u, u, u)` for a unit `u`.
    pub(crate) fn inverse_young_unit(&self, u: [f64; 3]) -> f64 {
        contract(&self.compliance_tensor, u, u, u, u)
    }

    /// `1/G(u, v) = 4 s(u, v, u, v)` for unit, perpendicular `u`, `v`.
    pub(crate) fn inverse_shear_unit(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        4.0 * contract(&self.compliance_tensor, u, v, u, v)
    }

    /// `ν(u, v)` for unit, perpendicular `u`, `v`.
    pub(crate) fn poisson_unit(&self, u: [f64; 3], v: [f64; 3]) -> f64 {
        -contract(&self.compliance_tensor, u, u, v, v) / self.inverse_young_unit(u)
    }

    /// The symmetric 3x3 matrix `β_ij = Σ_k s_ijkk`: `β(u) = uᵀ β u`.
    pub fn compressibility_matrix(&self) -> [[f64; 3]; 3] {
        let s = &self.compliance_tensor;
        std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| s[i][j][k][k]).sum()))
    }

    /// [`Stiffness::shear_min_max`] for a unit `u`.
    pub(crate) fn shear_min_max_unit(&self, u: [f64; 3]) -> PlaneExtremes {
        let form = partial_contract_13(&self.compliance_tensor, u, u);
        let (a, b) = plane_eigenvectors(&form, u);
        let (ga, gb) = (
            1.0 / self.inverse_shear_unit(u, a),
            1.0 / self.inverse_shear_unit(u, b),
        );
        ordered(ga, a, gb, b)
    }

    /// [`Stiffness::poisson_min_max`] for a unit `u`.
    pub(crate) fn poisson_min_max_unit(&self, u: [f64; 3]) -> PlaneExtremes {
        let form = partial_contract_12(&self.compliance_tensor, u, u);
        let (a, b) = plane_eigenvectors(&form, u);
        ordered(self.poisson_unit(u, a), a, self.poisson_unit(u, b), b)
    }
}

/// The min/max record of two values at two directions.
fn ordered(x: f64, xv: [f64; 3], y: f64, yv: [f64; 3]) -> PlaneExtremes {
    if x <= y {
        PlaneExtremes {
            min: x,
            max: y,
            min_v: xv,
            max_v: yv,
        }
    } else {
        PlaneExtremes {
            min: y,
            max: x,
            min_v: yv,
            max_v: xv,
        }
    }
}

/// The two unit eigenvectors (both ⊥ `u`) of the quadratic form `vᵀ M v` restricted to
/// the plane ⊥ unit `u`. `M` is symmetrised first.
fn plane_eigenvectors(m: &[[f64; 3]; 3], u: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let (e1, e2) = plane_basis(u);
    let form = |a: [f64; 3], b: [f64; 3]| {
        let mut sum = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                sum += 0.5 * (m[i][j] + m[j][i]) * a[i] * b[j];
            }
        }
        sum
    };
    let (p, q, r) = (form(e1, e1), form(e1, e2), form(e2, e2));
    // The eigenvectors of [[p, q], [q, r]] are at angles θ and θ + 90° from e1.
    let theta = 0.5 * (2.0 * q).atan2(p - r);
    let (sin, cos) = theta.sin_cos();
    let a = std::array::from_fn(|i| cos * e1[i] + sin * e2[i]);
    let b = std::array::from_fn(|i| -sin * e1[i] + cos * e2[i]);
    (a, b)
}

/// An orthonormal basis of the plane ⊥ unit `u`.
pub(crate) fn plane_basis(u: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    // Cross with the coordinate axis least aligned with u: never near-parallel.
    let axis = (0..3)
        .min_by(|&i, &j| u[i].abs().total_cmp(&u[j].abs()))
        .unwrap_or(0);
    let mut a = [0.0; 3];
    a[axis] = 1.0;
    let e1 = normalized(cross(u, a));
    let e2 = cross(u, e1);
    (e1, e2)
}

/// `u` scaled to unit length; refuses a zero or non-finite vector.
pub(crate) fn unit(u: [f64; 3], argument: &'static str) -> Result<[f64; 3], Error> {
    let scale = u.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    if !u.iter().all(|x| x.is_finite()) || scale == 0.0 {
        return Err(Error::BadDirection { argument });
    }
    // Scale first so that squaring cannot overflow or underflow.
    Ok(normalized(u.map(|x| x / scale)))
}

/// Unit `u`, `v` from the arguments; refuses a pair that is not perpendicular.
fn perpendicular_pair(u: [f64; 3], v: [f64; 3]) -> Result<([f64; 3], [f64; 3]), Error> {
    let (u, v) = (unit(u, "u")?, unit(v, "v")?);
    let cosine = dot(u, v);
    if cosine.abs() > PERPENDICULAR_TOLERANCE {
        return Err(Error::NotPerpendicular { cosine });
    }
    Ok((u, v))
}

/// `uᵀ M u`.
fn quadratic(m: &[[f64; 3]; 3], u: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| (0..3).map(|j| m[i][j] * u[i] * u[j]).sum::<f64>())
        .sum()
}

/// The dot product.
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a / |a|` (for a nonzero, finite `a`).
pub(crate) fn normalized(a: [f64; 3]) -> [f64; 3] {
    let norm = dot(a, a).sqrt();
    a.map(|x| x / norm)
}

/// Refuses a matrix with a NaN or infinite entry, naming the first in row order.
fn check_finite(c: &Voigt) -> Result<(), Error> {
    for (i, row) in c.iter().enumerate() {
        if let Some(j) = row.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                row: i + 1,
                column: j + 1,
            });
        }
    }
    Ok(())
}

/// Refuses a matrix with `|C_ij - C_ji| > 1e-6 · max|C|`, naming the first such pair.
fn check_symmetric(c: &Voigt) -> Result<(), Error> {
    let largest = largest_entry(c);
    let mut upper_pairs = (0..6).flat_map(|i| (i + 1..6).map(move |j| (i, j)));
    match upper_pairs.find(|&(i, j)| (c[i][j] - c[j][i]).abs() > SYMMETRY_TOLERANCE * largest) {
        Some((i, j)) => Err(Error::NotSymmetric {
            row: i + 1,
            column: j + 1,
            upper: c[i][j],
            lower: c[j][i],
        }),
        None => Ok(()),
    }
}

/// `max |C_ij|`.
fn largest_entry(c: &Voigt) -> f64 {
    c.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// `(A + Aᵀ) / 2`.
fn symmetric_part(a: &Voigt) -> Voigt {
    std::array::from_fn(|i| std::array::from_fn(|j| 0.5 * (a[i][j] + a[j][i])))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An isotropic stiffness from the Lamé constants.
    fn isotropic(lambda: f64, mu: f64) -> Voigt {
        std::array::from_fn(|i| {
            std::array::from_fn(|j| match (i < 3, j < 3) {
                (true, true) => lambda + if i == j { 2.0 * mu } else { 0.0 },
                _ if i == j => mu,
                _ => 0.0,
            })
        })
    }

    #[test]
    fn compliance_is_the_inverse() {
        let mut c = isotropic(50.0, 30.0);
        c[0][3] = 5.0;
        c[3][0] = 5.0;
        let stiffness = Stiffness::new(c).unwrap();
        let s = stiffness.compliance();
        let product: Voigt = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..6).map(|k| c[i][k] * s[k][j]).sum())
        });
        for (i, row) in product.iter().enumerate() {
            for (j, entry) in row.iter().enumerate() {
                let identity = if i == j { 1.0 } else { 0.0 };
                assert!((entry - identity).abs() < 1e-12, "({i},{j}): {entry}");
            }
        }
    }

    #[test]
    fn refusals_name_the_entry() {
        let mut c = isotropic(50.0, 30.0);
        c[2][4] = f64::NAN;
        assert_eq!(
            Stiffness::new(c),
            Err(Error::NonFinite { row: 3, column: 5 })
        );
        let mut c = isotropic(50.0, 30.0);
        c[1][5] = 1.0;
        let error = Stiffness::new(c).unwrap_err();
        assert_eq!(
            error,
            Error::NotSymmetric {
                row: 2,
                column: 6,
                upper: 1.0,
                lower: 0.0
            }
        );
        assert!(error.to_string().contains("C26"), "{error}");
        // Asymmetry within 1e-6 · max|C| is accepted (and symmetrised).
        let mut c = isotropic(50.0, 30.0);
        c[1][5] = 1e-5;
        assert_eq!(Stiffness::new(c).unwrap().voigt()[1][5], 0.5e-5);
    }

    #[test]
    fn unstable_and_singular() {
        // λ + 2μ/3 < 0: negative bulk modulus, eigenvalue 3λ + 2μ = -30.
        let c = isotropic(-30.0, 30.0);
        match Stiffness::new(c) {
            Err(Error::Unstable {
                smallest_eigenvalue,
            }) => assert!((smallest_eigenvalue + 30.0).abs() < 1e-9),
            other => panic!("{other:?}"),
        }
        let allowed = Options {
            allow_unstable: true,
        };
        let stiffness = Stiffness::with_options(c, allowed).unwrap();
        assert!(stiffness.linear_compressibility([1.0, 0.0, 0.0]).unwrap() < 0.0);
        // 3λ + 2μ = 0: singular.
        let c = isotropic(-20.0, 30.0);
        assert!(matches!(
            Stiffness::with_options(c, allowed),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            Stiffness::with_options([[0.0; 6]; 6], allowed),
            Err(Error::Singular { .. })
        ));
    }

    #[test]
    fn extreme_magnitudes_are_handled() {
        let c = isotropic(50.0, 30.0);
        let e = Stiffness::new(c).unwrap().young([1.0, 2.0, 3.0]).unwrap();
        for scale in [1e-300, 1e300] {
            let scaled = c.map(|row| row.map(|x| x * scale));
            let stiffness = Stiffness::new(scaled).unwrap();
            let ratio = stiffness.young([1.0, 2.0, 3.0]).unwrap() / (e * scale);
            assert!((ratio - 1.0).abs() < 1e-12, "{scale}: {ratio}");
        }
        // Subnormal stiffness: the compliance overflows; refused, not infinite.
        let tiny = c.map(|row| row.map(|x| x * 1e-320));
        assert!(matches!(Stiffness::new(tiny), Err(Error::Singular { .. })));
    }

    #[test]
    fn direction_refusals() {
        let stiffness = Stiffness::new(isotropic(50.0, 30.0)).unwrap();
        assert_eq!(
            stiffness.young([0.0; 3]),
            Err(Error::BadDirection { argument: "u" })
        );
        assert_eq!(
            stiffness.shear([1.0, 0.0, 0.0], [f64::INFINITY, 0.0, 0.0]),
            Err(Error::BadDirection { argument: "v" })
        );
        assert!(matches!(
            stiffness.poisson([1.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
            Err(Error::NotPerpendicular { .. })
        ));
        // Huge and tiny lengths are fine.
        let e = stiffness.young([1e300, 1e300, 0.0]).unwrap();
        assert!((e - stiffness.young([1e-300, 1e-300, 0.0]).unwrap()).abs() < 1e-9);
    }

    #[test]
    fn plane_basis_is_orthonormal() {
        for u in [
            [1.0, 0.0, 0.0],
            [0.0, 0.0, -1.0],
            normalized([1.0, 2.0, 3.0]),
        ] {
            let (a, b) = plane_basis(u);
            for (x, y, expected) in [
                (a, a, 1.0),
                (b, b, 1.0),
                (a, b, 0.0),
                (a, u, 0.0),
                (b, u, 0.0),
            ] {
                assert!((dot(x, y) - expected).abs() < 1e-15);
            }
        }
    }
}
