//! TEMPORARY stand-in for `crate::glyph::sh` (written concurrently on another branch),
//! with the same names and signatures, so that this branch builds and its SH-fit tests
//! run. Delete this file at the merge; `fit/mod.rs` then says `use crate::glyph::sh;`.
//!
//! It is an honest implementation, not a dummy: real SH of SCENE-FORMAT.md (complex Y_l^m
//! with the Condon-Shortley phase, orthonormal, the tournier07 and descoteaux07 bases and
//! their legacy variants) and the Laplace-Beltrami regularised least squares of
//! Descoteaux et al., "Regularized, fast, and robust analytical Q-ball imaging", MRM 58,
//! 2007: c = (B^T B + lambda L)^-1 B^T s with L = diag(l^2 (l+1)^2).
use glam::DVec3;
use nalgebra::DMatrix;

use crate::io::scene::ShBasis;
use crate::{Error, Result};

/// (L+1)(L+2)/2 coefficients for even bands 0, 2, ..., L.
pub fn sh_count(band: u32) -> usize {
    ((band + 1) * (band + 2) / 2) as usize
}

/// Regularised least-squares SH fit on a fixed set of directions.
#[derive(Clone, Debug)]
pub struct ShFitter {
    /// B, directions x coefficients.
    basis_matrix: DMatrix<f64>,
    /// (B^T B + lambda L)^-1 B^T, coefficients x directions.
    fit_matrix: DMatrix<f64>,
}

impl ShFitter {
    pub fn new(
        band: u32,
        basis: ShBasis,
        legacy: bool,
        directions: &[DVec3],
        lambda: f64,
    ) -> Result<Self> {
        if band % 2 == 1 || band > 12 {
            return Err(Error::Invalid(format!(
                "SH band {band} must be even and at most 12"
            )));
        }
        if !(lambda.is_finite() && lambda >= 0.0) {
            return Err(Error::Invalid(format!("lambda {lambda} must be >= 0")));
        }
        let count = sh_count(band);
        let rows: Vec<f64> = directions
            .iter()
            .flat_map(|&u| real_sh_row(band, basis, legacy, u))
            .collect();
        let b = DMatrix::from_row_slice(directions.len(), count, &rows);
        let mut normal = b.transpose() * &b;
        for (l, m_count) in (0..=band).step_by(2).map(|l| (l, 2 * l + 1)) {
            let penalty = lambda * (l * l * (l + 1) * (l + 1)) as f64;
            let first = sh_count(l) - m_count as usize;
            for i in first..first + m_count as usize {
                normal[(i, i)] += penalty;
            }
        }
        let inverse = normal
            .cholesky()
            .ok_or_else(|| Error::Invalid("SH normal equations are singular".into()))?
            .inverse();
        Ok(Self {
            fit_matrix: inverse * b.transpose(),
            basis_matrix: b,
        })
    }

    pub fn fit(&self, samples: &[f64]) -> Vec<f64> {
        matrix_times(&self.fit_matrix, samples)
    }

    pub fn fitted_values(&self, coeffs: &[f64]) -> Vec<f64> {
        matrix_times(&self.basis_matrix, coeffs)
    }
}

fn matrix_times(m: &DMatrix<f64>, v: &[f64]) -> Vec<f64> {
    (0..m.nrows())
        .map(|i| m.row(i).iter().zip(v).map(|(a, b)| a * b).sum())
        .collect()
}

/// All basis functions at u, at index l(l+1)/2 + m.
fn real_sh_row(band: u32, basis: ShBasis, legacy: bool, u: DVec3) -> Vec<f64> {
    let u = u.normalize();
    let (cos_theta, phi) = (u.z.clamp(-1.0, 1.0), u.y.atan2(u.x));
    let mut row = Vec::with_capacity(sh_count(band));
    for l in (0..=band as i32).step_by(2) {
        for m in -l..=l {
            let k = m.abs();
            let magnitude = normalised_legendre(l, k, cos_theta);
            let (re, im) = (
                magnitude * (k as f64 * phi).cos(),
                magnitude * (k as f64 * phi).sin(),
            );
            let root2 = std::f64::consts::SQRT_2;
            let value = match (basis, m.signum()) {
                (_, 0) => re,
                (ShBasis::Tournier07, -1) => {
                    if legacy {
                        im
                    } else {
                        root2 * im
                    }
                }
                (ShBasis::Tournier07, _) => {
                    if legacy {
                        re
                    } else {
                        root2 * re
                    }
                }
                // Re Y_l^-k = (-1)^k Re Y_l^k.
                (ShBasis::Descoteaux07, -1) => {
                    let sign = if legacy || k % 2 == 0 { 1.0 } else { -1.0 };
                    root2 * sign * re
                }
                (ShBasis::Descoteaux07, _) => root2 * im,
            };
            row.push(value);
        }
    }
    row
}

/// sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(x), with the Condon-Shortley phase, m >= 0.
fn normalised_legendre(l: i32, m: i32, x: f64) -> f64 {
    let s = (1.0 - x * x).max(0.0).sqrt();
    let mut p_mm = 1.0;
    for i in 1..=m {
        p_mm *= -((2 * i - 1) as f64) * s;
    }
    let (mut previous, mut current) = (0.0, p_mm);
    for n in m + 1..=l {
        let next =
            ((2 * n - 1) as f64 * x * current - (n + m - 1) as f64 * previous) / (n - m) as f64;
        previous = current;
        current = next;
    }
    let ratio: f64 = (l - m + 1..=l + m).map(|v| 1.0 / v as f64).product();
    ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI) * ratio).sqrt() * current
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::polynomial::test_support::Rng;

    #[test]
    fn known_values_and_exact_fit_of_a_band_two_function() {
        let y00 = 0.5 / std::f64::consts::PI.sqrt();
        assert!((real_sh_row(0, ShBasis::Tournier07, false, DVec3::X)[0] - y00).abs() < 1e-15);
        // Y_2^0 = sqrt(5/16pi) (3 cos^2 - 1).
        let y20 = (5.0 / (16.0 * std::f64::consts::PI)).sqrt() * 2.0;
        assert!((real_sh_row(2, ShBasis::Descoteaux07, true, DVec3::Z)[3] - y20).abs() < 1e-14);
        let mut rng = Rng::new(9);
        let dirs: Vec<DVec3> = (0..60).map(|_| rng.unit_vector()).collect();
        let samples: Vec<f64> = dirs.iter().map(|u| u.x * u.y + 0.3 * u.z * u.z).collect();
        for basis in [ShBasis::Tournier07, ShBasis::Descoteaux07] {
            for legacy in [false, true] {
                let fitter = ShFitter::new(4, basis, legacy, &dirs, 0.0).unwrap();
                let fitted = fitter.fitted_values(&fitter.fit(&samples));
                for (a, b) in fitted.iter().zip(&samples) {
                    assert!((a - b).abs() < 1e-10);
                }
            }
        }
    }
}
