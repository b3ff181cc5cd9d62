//! Rotation of an SH glyph: the coefficients of g(u) = f(R^T u).
//!
//! Each band is invariant under orthogonal maps (rotations and reflections), so g is a
//! series of the same band and basis; sampling g on a well-spread point set and fitting
//! (lambda = 0) recovers it exactly up to rounding. The points are a Fibonacci lattice
//! with three times as many points as coefficients, which keeps the SH basis matrix
//! well conditioned (measured in the tests); its pseudo-inverse is cached per basis.
use std::sync::Arc;

use glam::{DMat3, DVec3};

use super::cache::{BasisKey, Cache, cached};
use super::{ShFitter, check_coefficients, sh_count, sh_eval};
use crate::Result;
use crate::glyph::rotate::check_orthogonal;
use crate::glyph::sh::ShBasis;

static FITTERS: Cache<BasisKey, ShFitter> = Cache::new();

/// The coefficients of g(u) = f(R^T u) for the series f, R orthogonal (det +1 or -1).
pub fn rotate_sh(
    band: u32,
    basis: ShBasis,
    legacy: bool,
    coeffs: &[f64],
    r: DMat3,
) -> Result<Vec<f64>> {
    check_coefficients(band, coeffs)?;
    check_orthogonal(r)?;
    let fitter = rotation_fitter(band, basis, legacy)?;
    let rt = r.transpose();
    let samples: Vec<f64> = fitter
        .directions()
        .iter()
        .map(|u| sh_eval(band, basis, legacy, coeffs, rt * *u))
        .collect();
    Ok(fitter.fit(&samples))
}

fn rotation_fitter(band: u32, basis: ShBasis, legacy: bool) -> Result<Arc<ShFitter>> {
    cached(&FITTERS, BasisKey::new(band, basis, legacy), || {
        let points = fibonacci_sphere(3 * sh_count(band) + 30);
        ShFitter::new(band, basis, legacy, &points, 0.0)
    })
}

/// n points of the Fibonacci (golden-angle) lattice on the unit sphere: z uniform in
/// (-1, 1) at cell centres, azimuth advancing by the golden angle.
pub(crate) fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden_angle = std::f64::consts::PI * (3.0 - 5.0f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden_angle * i as f64;
            DVec3::new(s * phi.cos(), s * phi.sin(), z)
        })
        .collect()
}
