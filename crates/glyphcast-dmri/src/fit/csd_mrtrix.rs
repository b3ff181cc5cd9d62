//! Constrained spherical deconvolution as MRtrix3 computes it (`dwi2fod csd`, version
//! 3.0; Tournier et al. 2007, NeuroImage 35), beside DIPY's variant in `csd`. Both
//! solve the same problem: f minimises |X f - S|^2 + |H f|^2, X = B diag(R_l) the
//! convolution with the response (R_l = sqrt(4 pi / (2l+1)) r_l, Funk-Hecke) and H the
//! constraint rows of the directions where the estimate is negative. They differ in
//! the details, which move peaks by a few degrees (a median of 3.6 on small_64D):
//!
//! | | MRtrix (here) | DIPY (`csd`) |
//! |---|---|---|
//! | constraint directions | 300, electrostatic repulsion | 181 (geodesic hemisphere) |
//! | constraint weight | neg_lambda 50 r_0 / N (N = 300) | lambda k R_0 / (sqrt(N) sqrt(362)) (N = 181) |
//! | constrained where | f(u) < threshold (0, absolute) | f(u) < tau (0.1) times the mean |
//! | minimum norm | + 2e-4 (X^T X)_00 I (norm_lambda 1) | none |
//! | first estimate | bands 0 to 4 of a damped lmax-L_i fit | the unconstrained fit |
//!
//! The response is read as MRtrix writes it (`response`: zonal coefficients r_l in
//! signal units), and R_l is what MRtrix convolves with: r_l divided by Y_l^0 at the
//! pole, sqrt((2l+1)/(4 pi)). So an fODF amplitude here is `dwi2fod`'s for the same
//! response file.
//!
//! The first estimate (MRtrix's `-filter` 1 1 1): the basis matrix at the acquisition
//! directions up to L_i = min(response band, the data's band, L) with 0.01 added to its
//! diagonal entries, pseudo-inverted, each band divided by R_l; bands above 4 set to 0.
//! Then, up to [`MAX_ITERATIONS`] times, the directions where the estimate falls below
//! the threshold are chosen and the regularised normal equations
//! (X^T X + norm I + H^T H) f = X^T S solved, until the chosen set repeats.
//!
//! The series is computed in the orthonormal tournier07 basis, MRtrix's own, in the
//! DWI's voxel axes (`gradients`): the first estimate's diagonal damping depends on the
//! basis and the order of the coefficients, so it is taken where MRtrix takes it; MRtrix
//! works in scanner axes, which changes only that damping (measured in
//! tests/csd_mrtrix.rs: the fODFs agree to float32 rounding on small_64D).
//!
//! The signal is each voxel's diffusion-weighted samples in signal units, as `dwi2fod`
//! takes them, with one difference shared with every fit (`voxel`): a sample at or
//! below 0 is raised to 0.1 % of S0 where `dwi2fod` sets it to 0 (5 of small_64D's
//! 1000 voxels hold one).
//!
//! MRtrix's 300 constraint directions are a table it ships; glyphcast makes its own set
//! the same way ([`repulsion_directions`]: 300 axes spread by the repulsion of antipodal
//! charge pairs, 1/r, as `dirgen` does), from a fixed start. Two such sets give first
//! peaks a median of 0.14 degrees apart (measured with `dwi2fod -directions`).
use std::sync::OnceLock;

use glam::DVec3;
use nalgebra::{DMatrix, DVector};

use super::csd::set_changes;
use super::response::Response;
use crate::setting::DmriSetting;
use glyphcast::error::Problem;
use glyphcast::glyph::sh::{convert_basis, sh_basis_values, sh_count, sh_orders};
use glyphcast::scene::ShBasis;
use glyphcast::{Error, Result};

/// Which CSD `fit --odf csd` runs (`--csd-algorithm`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CsdAlgorithm {
    /// MRtrix3's `dwi2fod csd` (this module).
    #[default]
    Mrtrix,
    /// DIPY's `ConstrainedSphericalDeconvModel` (`csd`).
    Dipy,
}

impl CsdAlgorithm {
    /// The name `--csd-algorithm` takes.
    pub fn name(self) -> &'static str {
        match self {
            CsdAlgorithm::Mrtrix => "mrtrix",
            CsdAlgorithm::Dipy => "dipy",
        }
    }

    /// Parses `mrtrix` or `dipy` (any case); Err names what was given.
    pub fn parse(name: &str) -> Result<Self> {
        let lower = name.trim().to_ascii_lowercase();
        [CsdAlgorithm::Mrtrix, CsdAlgorithm::Dipy]
            .into_iter()
            .find(|a| a.name() == lower)
            .ok_or_else(|| {
                Error::setting_value(
                    DmriSetting::CsdAlgorithm,
                    format!("'{}'", glyphcast::error::quoted(name)),
                    "expected mrtrix or dipy",
                )
            })
    }
}

/// Default weight of the non-negativity constraint (`dwi2fod -neg_lambda`).
pub const DEFAULT_NEG_LAMBDA: f64 = 1.0;

/// Default weight of the minimum-norm term (`dwi2fod -norm_lambda`).
pub const DEFAULT_NORM_LAMBDA: f64 = 1.0;

/// Default threshold below which the fODF amplitude is constrained (`dwi2fod
/// -threshold`): an absolute amplitude, in the fODF's units.
pub const DEFAULT_THRESHOLD: f64 = 0.0;

/// The thresholds `dwi2fod -threshold` accepts.
pub const THRESHOLD_RANGE: std::ops::RangeInclusive<f64> = -1.0..=10.0;

/// Solves before giving up (`dwi2fod -niter`); the last solve is kept.
pub const MAX_ITERATIONS: usize = 50;

/// The number of constraint directions (MRtrix's default set has 300).
pub const CONSTRAINT_DIRECTIONS: usize = 300;

/// The constraint rows are scaled by neg_lambda times this times r_0 over the number of
/// directions.
const CONSTRAINT_SCALE: f64 = 50.0;

/// The minimum-norm weight is norm_lambda times this times (X^T X)_00.
const NORM_SCALE: f64 = 2e-4;

/// Added to the diagonal entries of the first estimate's basis matrix.
const FIRST_ESTIMATE_DAMPING: f64 = 0.01;

/// The bands the first estimate keeps (MRtrix's default filter: 1 for l = 0, 2, 4).
const FIRST_ESTIMATE_BAND: u32 = 4;

/// The basis the solve runs in: MRtrix's (orthonormal tournier07).
const SOLVE_BASIS: (ShBasis, bool) = (ShBasis::Tournier07, false);

/// Gradient-descent steps of [`repulsion_directions`].
const REPULSION_STEPS: usize = 200;

/// A `dwi2fod csd` solve prepared for one gradient table and response.
#[derive(Clone, Debug)]
pub struct MrtrixCsdFitter {
    /// The first estimate from the signal, coefficients x directions (bands above
    /// [`FIRST_ESTIMATE_BAND`] are zero rows).
    first: DMatrix<f64>,
    /// X = B diag(R_l), directions x coefficients.
    design: DMatrix<f64>,
    /// X^T X + norm I.
    normal: DMatrix<f64>,
    /// The constraint directions' basis rows times the constraint weight.
    constraint: DMatrix<f64>,
    /// Its transpose: one constraint row per column.
    constraint_rows: DMatrix<f64>,
    /// The threshold in the constraint rows' units.
    threshold: f64,
    /// The solve basis to the requested basis.
    output: DMatrix<f64>,
}

/// The parameters of `dwi2fod csd` that glyphcast exposes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MrtrixCsdParameters {
    /// Weight of the non-negativity constraint (`-neg_lambda`, default 1).
    pub neg_lambda: f64,
    /// Weight of the minimum-norm term (`-norm_lambda`, default 1).
    pub norm_lambda: f64,
    /// The absolute fODF amplitude below which the constraint acts (`-threshold`,
    /// default 0), in the fODF's units.
    pub threshold: f64,
}

impl Default for MrtrixCsdParameters {
    fn default() -> Self {
        Self {
            neg_lambda: DEFAULT_NEG_LAMBDA,
            norm_lambda: DEFAULT_NORM_LAMBDA,
            threshold: DEFAULT_THRESHOLD,
        }
    }
}

impl MrtrixCsdFitter {
    /// The solve for `directions` (one per diffusion-weighted volume), `response` and
    /// the fODF up to `band` in `basis`, constrained at glyphcast's 300 repulsion
    /// directions. Err when the response has no positive band 0, no anisotropic band,
    /// or a zero among the bands of the first estimate ([`check_response`]).
    pub fn new(
        band: u32,
        basis: (ShBasis, bool),
        directions: &[DVec3],
        response: &Response,
        parameters: MrtrixCsdParameters,
    ) -> Result<Self> {
        let constraint = default_constraint_directions();
        Self::with_constraint(band, basis, directions, response, parameters, constraint)
    }

    /// [`MrtrixCsdFitter::new`] constrained at `constraint` (unit vectors in the
    /// directions' frame; `dwi2fod -directions`).
    pub fn with_constraint(
        band: u32,
        basis: (ShBasis, bool),
        directions: &[DVec3],
        response: &Response,
        parameters: MrtrixCsdParameters,
        constraint: &[DVec3],
    ) -> Result<Self> {
        check_response(response)
            .map_err(|why| Error::input("the response", "zonal coefficients", why))?;
        if constraint.is_empty() {
            return Err(Error::data("CSD's constraint directions", Problem::Empty));
        }
        let r0 = response.zonal[0];
        let factors: Vec<f64> = sh_orders(band)
            .map(|(l, _)| response.convolution_factor(l))
            .collect();
        let first = first_estimate(band, directions, response)?;
        let mut design = basis_matrix(band, directions);
        for (j, factor) in factors.iter().enumerate() {
            design.column_mut(j).scale_mut(*factor);
        }
        let mut normal = design.tr_mul(&design);
        let norm = parameters.norm_lambda * NORM_SCALE * normal[(0, 0)];
        for i in 0..normal.nrows() {
            normal[(i, i)] += norm;
        }
        let weight = parameters.neg_lambda * CONSTRAINT_SCALE * r0 / constraint.len() as f64;
        let constraint = basis_matrix(band, constraint) * weight;
        Ok(Self {
            first,
            design,
            normal,
            constraint_rows: constraint.transpose(),
            constraint,
            threshold: parameters.threshold * weight,
            output: basis_change(band, basis)?,
        })
    }

    /// The fODF of one voxel's diffusion-weighted signal (one value per direction, signal
    /// units) into `coeffs`; returns the number of solves (at most [`MAX_ITERATIONS`]).
    pub fn fit_into(&self, signal: &[f64], coeffs: &mut [f64]) -> usize {
        let signal = DVector::from_column_slice(signal);
        let rhs = self.design.tr_mul(&signal);
        let mut f = &self.first * &signal;
        // No set yet: the first choice is solved even when it is empty.
        let mut previous: Option<Vec<usize>> = None;
        // X^T X + norm I + H^T H, updated by the rows that enter or leave the set: between
        // solves the set changes by a few directions, not all of them.
        let mut q = self.normal.clone();
        let mut solves = 0;
        while solves < MAX_ITERATIONS {
            let below = self.below(&f);
            if previous.as_ref() == Some(&below) {
                break;
            }
            let current = previous.as_deref().unwrap_or(&[]);
            for (i, sign) in set_changes(current, &below) {
                let row = self.constraint_rows.column(i);
                q.ger(sign, &row, &row, 1.0);
            }
            f = solve(q.clone(), &rhs);
            previous = Some(below);
            solves += 1;
        }
        let out = &self.output * f;
        coeffs.copy_from_slice(out.as_slice());
        solves
    }

    /// The constraint directions where `f` is below the threshold.
    fn below(&self, f: &DVector<f64>) -> Vec<usize> {
        (&self.constraint * f)
            .iter()
            .enumerate()
            .filter(|(_, v)| **v < self.threshold)
            .map(|(i, _)| i)
            .collect()
    }
}

/// What MRtrix's CSD asks of a response: a positive band 0, an anisotropic band (MRtrix
/// refuses a response of band 0 alone), and no zero among the bands of the first
/// estimate, which divides by them. Err says which.
pub fn check_response(response: &Response) -> std::result::Result<(), String> {
    let r0 = response.zonal.first().copied().unwrap_or(0.0);
    if r0.is_nan() || r0 <= 0.0 {
        return Err(format!(
            "the response's l=0 coefficient must be positive, found {r0}"
        ));
    }
    if response.band() == 0 {
        return Err(
            "the response has only its l=0 coefficient: MRtrix's CSD needs an anisotropic \
             response (bands 0 and 2 at least)"
                .into(),
        );
    }
    let first = response.band().min(FIRST_ESTIMATE_BAND) as usize / 2;
    match response.zonal[..=first].iter().position(|&r| r == 0.0) {
        Some(i) => Err(format!(
            "the response's l={} coefficient is 0: CSD's first estimate divides by it",
            2 * i
        )),
        None => Ok(()),
    }
}

/// The first estimate's map from the signal to the coefficients up to `band` (see the
/// module notes).
fn first_estimate(band: u32, directions: &[DVec3], response: &Response) -> Result<DMatrix<f64>> {
    let data_band = (0..=band)
        .step_by(2)
        .take_while(|&l| sh_count(l) <= directions.len())
        .last()
        .unwrap_or(0);
    let low = response.band().min(data_band).min(band);
    let mut damped = basis_matrix(low, directions);
    for i in 0..damped.nrows().min(damped.ncols()) {
        damped[(i, i)] += FIRST_ESTIMATE_DAMPING;
    }
    let inverse = damped.pseudo_inverse(1e-12).map_err(|e| Error::Numerical {
        step: "CSD's first estimate",
        detail: e.to_string(),
    })?;
    let mut first = DMatrix::zeros(sh_count(band), directions.len());
    for (row, (l, _)) in sh_orders(low).enumerate() {
        if l > FIRST_ESTIMATE_BAND {
            break;
        }
        let factor = response.convolution_factor(l);
        first.set_row(row, &(inverse.row(row) / factor));
    }
    Ok(first)
}

/// The solve basis at `directions`: one row per direction.
fn basis_matrix(band: u32, directions: &[DVec3]) -> DMatrix<f64> {
    let values: Vec<f64> = directions
        .iter()
        .flat_map(|u| sh_basis_values(band, SOLVE_BASIS.0, SOLVE_BASIS.1, *u))
        .collect();
    DMatrix::from_row_slice(directions.len(), sh_count(band), &values)
}

/// The matrix that maps coefficients in [`SOLVE_BASIS`] to `to`.
fn basis_change(band: u32, to: (ShBasis, bool)) -> Result<DMatrix<f64>> {
    let k = sh_count(band);
    let mut change = DMatrix::zeros(k, k);
    let mut unit = vec![0.0; k];
    for j in 0..k {
        unit[j] = 1.0;
        let column = convert_basis(band, SOLVE_BASIS, to, &unit)?;
        change.column_mut(j).copy_from_slice(&column);
        unit[j] = 0.0;
    }
    Ok(change)
}

/// Solves the symmetric positive definite q x = z by Cholesky; q is singular only when
/// norm_lambda is 0 and the directions leave coefficients undetermined, where the
/// pseudo-inverse gives the least-norm solution.
fn solve(q: DMatrix<f64>, z: &DVector<f64>) -> DVector<f64> {
    match q.clone().cholesky() {
        Some(c) => c.solve(z),
        None => q
            .pseudo_inverse(1e-12)
            .map(|p| p * z)
            .unwrap_or_else(|_| DVector::zeros(z.len())),
    }
}

/// glyphcast's [`CONSTRAINT_DIRECTIONS`] repulsion directions, made once.
pub fn default_constraint_directions() -> &'static [DVec3] {
    static SET: OnceLock<Vec<DVec3>> = OnceLock::new();
    SET.get_or_init(|| repulsion_directions(CONSTRAINT_DIRECTIONS))
}

/// `count` axes spread over the sphere as `dirgen` spreads them: each axis is a pair of
/// antipodal unit charges, and the energy sum 1/r over all pairs of charges is lowered
/// by gradient descent on the sphere. The start is a golden-angle spiral on the upper
/// hemisphere, so the set is the same on every run.
pub fn repulsion_directions(count: usize) -> Vec<DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut axes: Vec<DVec3> = (0..count)
        .map(|i| {
            let z = 1.0 - (i as f64 + 0.5) / count as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden * i as f64;
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect();
    // The largest move per step, a fraction of the spacing of `count` axes, shrinking.
    let mut step = 0.2 * (2.0 * std::f64::consts::PI / count.max(1) as f64).sqrt();
    for _ in 0..REPULSION_STEPS {
        let forces: Vec<DVec3> = axes
            .iter()
            .enumerate()
            .map(|(i, &u)| {
                let force = axes
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .flat_map(|(_, &v)| [u - v, u + v])
                    .map(|d| d / d.length().powi(3))
                    .sum::<DVec3>();
                force - u * force.dot(u)
            })
            .collect();
        let largest = forces.iter().map(|f| f.length()).fold(0.0, f64::max);
        if largest == 0.0 {
            break;
        }
        for (u, f) in axes.iter_mut().zip(&forces) {
            *u = (*u + *f * (step / largest)).normalize();
        }
        step *= 0.98;
    }
    axes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repulsion_spreads_the_axes_evenly() {
        let axes = repulsion_directions(CONSTRAINT_DIRECTIONS);
        let angle = |a: DVec3, b: DVec3| a.dot(b).abs().min(1.0).acos().to_degrees();
        let nearest: Vec<f64> = axes
            .iter()
            .enumerate()
            .map(|(i, &u)| {
                axes.iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, &v)| angle(u, v))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        let (lo, hi) = nearest
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &a| {
                (lo.min(a), hi.max(a))
            });
        eprintln!("nearest neighbour: {lo:.2} to {hi:.2} degrees");
        // 600 charges on the sphere: about 8.9 degrees apart on a perfect hexagonal grid.
        assert!(lo > 7.5 && hi < 10.5, "{lo} {hi}");
        // Even in every direction: the second moment is 1/3 I.
        let mut moment = glam::DMat3::ZERO;
        for u in &axes {
            moment += glam::DMat3::from_cols(*u * u.x, *u * u.y, *u * u.z);
        }
        moment *= 1.0 / axes.len() as f64;
        for c in 0..3 {
            for r in 0..3 {
                let expected = if c == r { 1.0 / 3.0 } else { 0.0 };
                assert!((moment.col(c)[r] - expected).abs() < 2e-3, "{moment}");
            }
        }
    }
}
