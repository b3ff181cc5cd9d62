//! Constrained spherical deconvolution (Tournier et al. 2007, NeuroImage 35, Sec. 2):
//! the signal is the fODF convolved with the single-fibre response, which in SH is a
//! per-band factor (Funk-Hecke): S_lm = sqrt(4 pi / (2l+1)) r_l f_lm. With
//! X = B diag(sqrt(4 pi/(2l+1)) r_l) (B: the basis at the acquisition directions), the
//! fODF f minimises |X f - S|^2 + |H f|^2, where H holds the rows lambda' B_reg(u) of the
//! constraint sphere's directions u at which the current estimate falls below
//! tau times its mean. Starting from the unconstrained fit, truncated to l <= 4 for the
//! first choice of rows, the choice and the solve alternate until the rows stop
//! changing (at most [`MAX_ITERATIONS`]).
//!
//! Parameters and their scaling follow DIPY's `ConstrainedSphericalDeconvModel`, so
//! that its defaults mean the same here: tau = 0.1 and lambda = 1, with
//! lambda' = lambda k r'_0 / (sqrt(N) sqrt(362)), k the number of coefficients, N the
//! number of constraint directions and r'_0 = sqrt(4 pi) r_0 the band-0 factor. The
//! constraint directions are one hemisphere (181) of the geodesic sphere of 362
//! directions (`sphere`): the fODF is antipodally symmetric, so the other half would
//! repeat each row.
//!
//! The signal is deconvolved in signal units (S, not S/S0), as the response is; an fODF
//! amplitude is then proportional to the voxel's signal (apparent fibre density).
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

use super::basis::{WORK_BASIS, basis_change};
use super::response::Response;
use super::sphere::GeodesicSphere;
use glyphcast::error::Problem;
use glyphcast::glyph::sh::{sh_basis_values, sh_count, sh_orders};
use glyphcast::scene::ShBasis;
use glyphcast::{Error, Result};

/// Default weight of the non-negativity constraint.
pub const DEFAULT_CSD_LAMBDA: f64 = 1.0;

/// Default threshold, as a fraction of the mean fODF amplitude, below which a direction
/// is constrained.
pub const DEFAULT_CSD_TAU: f64 = 0.1;

/// Iterations of the constraint before giving up (the last estimate is kept).
pub const MAX_ITERATIONS: usize = 50;

/// Frequency of the constraint sphere: 10 * 6^2 + 2 = 362 directions.
const CONSTRAINT_SPHERE_FREQUENCY: usize = 6;

/// The band of the low-order first estimate.
pub(crate) const FIRST_ESTIMATE_BAND: u32 = 4;

/// A CSD solve prepared for one gradient table and response.
#[derive(Clone, Debug)]
pub struct CsdFitter {
    /// X = B R, directions x coefficients (work basis).
    design: DMatrix<f64>,
    /// X^T X.
    normal: DMatrix<f64>,
    /// lambda' B at the constraint directions.
    constraint: DMatrix<f64>,
    /// Its transpose: one constraint row per column.
    constraint_rows: DMatrix<f64>,
    tau: f64,
    /// Work basis to the requested basis.
    output: DMatrix<f64>,
}

/// The two weights of DIPY's CSD (`csdeconv`'s `lambda_` and `tau`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CsdParameters {
    /// Weight of the constraint rows, before the scaling of the module notes (DIPY: 1).
    pub lambda: f64,
    /// The threshold, as a fraction of the fODF's mean amplitude: directions where the
    /// fODF lies below it are penalised (DIPY: 0.1).
    pub tau: f64,
}

impl CsdFitter {
    /// The solve for `directions` (one per diffusion-weighted volume), `response` and
    /// the fODF up to `band` in `basis`, constrained on the geodesic hemisphere. Err
    /// when the directions do not determine the series, or the response has no
    /// positive band 0.
    pub fn new(
        band: u32,
        basis: (ShBasis, bool),
        directions: &[DVec3],
        response: &Response,
        parameters: CsdParameters,
    ) -> Result<Self> {
        let hemisphere = GeodesicSphere::hemisphere(CONSTRAINT_SPHERE_FREQUENCY);
        Self::with_constraint(band, basis, directions, response, parameters, &hemisphere)
    }

    /// [`CsdFitter::new`] with the constraint enforced at `constraint` (unit vectors)
    /// instead of the geodesic hemisphere.
    pub fn with_constraint(
        band: u32,
        basis: (ShBasis, bool),
        directions: &[DVec3],
        response: &Response,
        CsdParameters { lambda, tau }: CsdParameters,
        constraint: &[DVec3],
    ) -> Result<Self> {
        let k = sh_count(band);
        let factors: Vec<f64> = sh_orders(band)
            .map(|(l, _)| response.convolution_factor(l))
            .collect();
        if factors[0].is_nan() || factors[0] <= 0.0 {
            return Err(Error::data(
                "the response's band-0 coefficient",
                Problem::NotPositive {
                    value: response.zonal.first().copied().unwrap_or(0.0),
                },
            ));
        }
        let rows: Vec<f64> = directions
            .iter()
            .flat_map(|u| {
                sh_basis_values(band, WORK_BASIS.0, WORK_BASIS.1, *u)
                    .into_iter()
                    .zip(&factors)
                    .map(|(b, r)| b * r)
            })
            .collect();
        let design = DMatrix::from_row_slice(directions.len(), k, &rows);
        let normal = design.transpose() * &design;
        if constraint.is_empty() {
            return Err(Error::data("CSD's constraint directions", Problem::Empty));
        }
        let n_reg = constraint.len() as f64;
        let scaled = lambda * k as f64 * factors[0] / (n_reg.sqrt() * 362f64.sqrt());
        let rows: Vec<f64> = constraint
            .iter()
            .flat_map(|u| sh_basis_values(band, WORK_BASIS.0, WORK_BASIS.1, *u))
            .map(|v| v * scaled)
            .collect();
        let constraint = DMatrix::from_row_slice(constraint.len(), k, &rows);
        Ok(Self {
            design,
            normal,
            constraint_rows: constraint.transpose(),
            constraint,
            tau,
            output: basis_change(band, basis)?,
        })
    }

    /// The fODF of one voxel's diffusion-weighted signal (one value per direction, signal
    /// units) into `coeffs`; returns the number of constraint iterations.
    pub fn fit_into(&self, signal: &[f64], coeffs: &mut [f64]) -> usize {
        let k = self.normal.nrows();
        let z = self.design.tr_mul(&DVector::from_column_slice(signal));
        let mut f = solve(self.normal.clone(), &z);
        // The threshold: tau times the mean amplitude, f_00 Y_00 (scaled like the rows).
        let threshold = self.constraint[(0, 0)] * f[0] * self.tau;
        let low = sh_count(FIRST_ESTIMATE_BAND).min(k);
        let mut small = self.below(&f, low, threshold);
        if small.is_empty() {
            small = self.below(&f, k, threshold);
        }
        let mut iterations = 0;
        // Q = X^T X + H^T H, updated by the rows that enter or leave the set: between
        // iterations the set changes by a few directions, not all of them.
        let mut q = self.normal.clone();
        let mut active: Vec<usize> = Vec::new();
        while !small.is_empty() && iterations < MAX_ITERATIONS {
            iterations += 1;
            for (i, sign) in set_changes(&active, &small) {
                let row = self.constraint_rows.column(i);
                q.ger(sign, &row, &row, 1.0);
            }
            active.clone_from(&small);
            f = solve(q.clone(), &z);
            let next = self.below(&f, k, threshold);
            if next == small {
                break;
            }
            small = next;
        }
        let out = &self.output * f;
        coeffs.copy_from_slice(out.as_slice());
        iterations
    }

    /// Constraint directions where the series truncated to its first `count`
    /// coefficients is below `threshold`.
    fn below(&self, f: &DVector<f64>, count: usize, threshold: f64) -> Vec<usize> {
        let values = self.constraint.columns(0, count) * f.rows(0, count);
        values
            .iter()
            .enumerate()
            .filter(|(_, v)| **v < threshold)
            .map(|(i, _)| i)
            .collect()
    }
}

/// The members of sorted `next` missing from sorted `current` (sign 1) and those of
/// `current` missing from `next` (sign -1).
pub(crate) fn set_changes(current: &[usize], next: &[usize]) -> Vec<(usize, f64)> {
    let added = next
        .iter()
        .filter(|i| current.binary_search(i).is_err())
        .map(|&i| (i, 1.0));
    let removed = current
        .iter()
        .filter(|i| next.binary_search(i).is_err())
        .map(|&i| (i, -1.0));
    added.chain(removed).collect()
}

/// Solves the symmetric positive definite system q x = z by Cholesky, with a small ridge
/// when q is singular to working precision (DIPY adds 1e-5 I in that case).
fn solve(q: DMatrix<f64>, z: &DVector<f64>) -> DVector<f64> {
    let k = q.nrows();
    match q.clone().cholesky() {
        Some(c) => c.solve(z),
        None => {
            let ridge = q + DMatrix::identity(k, k) * 1e-5;
            ridge
                .cholesky()
                .map(|c| c.solve(z))
                .unwrap_or_else(|| DVector::zeros(k))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::peaks::{PeakFinder, PeakOptions};

    /// Signal of fibres along `fibres` (weights), each with the response of a prolate
    /// tensor, sampled at `directions`.
    fn crossing_signal(directions: &[DVec3], fibres: &[(DVec3, f64)]) -> Vec<f64> {
        let (b, s0, parallel, perpendicular) = (1000.0, 200.0, 1.7e-3, 0.3e-3);
        directions
            .iter()
            .map(|g| {
                fibres
                    .iter()
                    .map(|(d, w)| {
                        let c = g.dot(d.normalize());
                        w * s0 * (-b * (perpendicular + (parallel - perpendicular) * c * c)).exp()
                    })
                    .sum()
            })
            .collect()
    }

    #[test]
    fn resolves_a_known_crossing_that_the_signal_blurs() {
        let directions = GeodesicSphere::hemisphere(4);
        assert_eq!(directions.len(), 81);
        let one = DVec3::new(1.0, 0.2, 0.1).normalize();
        // 60 degrees from `one`, in a plane through it.
        let normal = one.any_orthonormal_vector();
        let two = one * 0.5 + normal * (3f64.sqrt() / 2.0);
        let signal = crossing_signal(&directions, &[(one, 0.6), (two, 0.4)]);
        let response = Response::from_tensor(1.7e-3, 0.3e-3, 200.0, 1000.0, 8);
        let basis = (ShBasis::Tournier07, false);
        let parameters = CsdParameters {
            lambda: 1.0,
            tau: 0.1,
        };
        let fitter = CsdFitter::new(8, basis, &directions, &response, parameters).unwrap();
        assert_eq!(fitter.constraint.nrows(), 181);
        let mut coeffs = vec![0.0; sh_count(8)];
        let iterations = fitter.fit_into(&signal, &mut coeffs);
        assert!(iterations < MAX_ITERATIONS);
        let finder = PeakFinder::new(8, basis.0, basis.1, PeakOptions::default()).unwrap();
        let peaks = finder.find(&coeffs);
        assert_eq!(peaks.len(), 2, "{peaks:?}");
        let angle = |a: DVec3, b: DVec3| a.dot(b).abs().min(1.0).acos().to_degrees();
        assert!(angle(peaks[0].direction, one) < 3.0, "{peaks:?}");
        assert!(angle(peaks[1].direction, two) < 3.0, "{peaks:?}");
        // The fODF integrates to the fibres' total weight: f_00 sqrt(4 pi) = 1 in units
        // of the response (the signal was made with weights 0.6 + 0.4).
        let total = coeffs[0] * (4.0 * std::f64::consts::PI).sqrt();
        assert!((total - 1.0).abs() < 0.05, "{total}");
    }
}
