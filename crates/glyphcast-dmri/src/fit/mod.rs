//! Fitting glyph coefficients to diffusion-weighted MRI: `glyphcast fit`.
//!
//! Two models, both linear least squares on a design that depends only on the gradient
//! directions, so the solve is factorised once and each voxel costs one matrix-vector
//! product:
//! - a symmetric tensor of even order n fitted to the apparent diffusion coefficients
//!   (generalised DTI, Özarslan and Mareci 2003; see `tensor`), output as the
//!   (n+1)(n+2)/2 unique coefficients of the scene format, in mm^2/s when the b-values
//!   are in s/mm^2;
//! - real SH up to an even band L fitted to the normalised signal S/S0 with
//!   Laplace-Beltrami regularisation (Descoteaux et al. 2007), in the scene format's
//!   SH bases;
//! - fibre ODFs as SH series (`odf`): CSA and Q-ball, linear in the same regularised SH
//!   fit, and constrained spherical deconvolution, as MRtrix computes it (`csd_mrtrix`)
//!   or as DIPY does (`csd`), with a response estimated from high-FA voxels or read from
//!   a file (`response`); `peaks` finds their maxima;
//! - multi-shell multi-tissue CSD (`msmt`): WM fODF, GM and CSF from all shells at once,
//!   a QP per voxel, with per-shell tissue responses (`response_msmt`).
//!
//! Signal conventions (`voxel`): S0 is the mean of the b=0 volumes (b <= 50 s/mm^2,
//! [`gradients::B0_THRESHOLD`]). A voxel whose S0 is not positive, or that holds a
//! non-finite sample, is left out: all its coefficients are 0. Left-out voxels are
//! counted by reason ([`FitReport`], which the command turns into warnings), and data in
//! which no voxel can be fitted is an error rather than an all-zero output. A sample at or below
//! zero is raised to [`voxel::SIGNAL_FLOOR`] S0 (0.1 % of S0) before use, so that the
//! logarithm of the ADC stays finite; the clamped direction then reads
//! ADC = ln(1000)/b, about 6.9e-3 mm^2/s at b = 1000, faster than free water, which is
//! what a signal lost in the noise floor means. The SH fit uses the same clamped ratio.
//!
//! Everything is validated before any voxel is fitted, and the output is written to a
//! temporary file next to the target and renamed (`output`), so a failed run leaves no
//! file behind.
mod basis;
pub mod csd;
pub mod csd_mrtrix;
pub mod dti;
pub mod dwi;
pub mod gradients;
pub mod inputs;
pub mod msmt;
pub mod odf;
pub mod output;
pub mod peaks;
pub mod response;
pub mod response_msmt;
pub mod sphere;
use glyphcast::glyph::sh;
pub mod tensor;
pub mod tissue;
pub mod voxel;

pub use csd_mrtrix::CsdAlgorithm;
pub use inputs::{FitFiles, FitInputs};
pub use odf::OdfMethod;
pub use response::Response;
pub use voxel::{FitReport, VoxelFitter, fit, fit_with_report, fit_with_response};

use crate::setting::DmriSetting;
use crate::volume::TENSOR_PREFIX;
use glyphcast::scene::{GlyphKind, ShBasis};
use glyphcast::{Error, Result, Setting};
use sh::sh_count;

/// The highest tensor order and SH band the scene format can draw.
pub const MAX_ORDER: u32 = glyphcast::catalog::MAX_SYMMETRIC_ORDER;

/// Default Laplace-Beltrami weight (Descoteaux et al. 2007 use 0.006).
pub const DEFAULT_LAMBDA: f64 = 0.006;

/// Largest accepted Laplace-Beltrami weight. With n evenly spread directions
/// (B^T B about n/(4 pi) I) the penalty divides a band-l coefficient by about
/// 1 + 4 pi lambda l^2 (l+1)^2 / n: at 1000 even band 2 keeps less than 0.1 % of itself
/// with 64 directions, so larger weights only flatten the glyph further; and from about
/// 1e16 the stacked system's condition number (about 70 sqrt(lambda)) passes the fit's
/// limit of 1e10, where the error would wrongly blame the directions.
pub const MAX_LAMBDA: f64 = 1000.0;

/// What to fit in each voxel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FitModel {
    /// Symmetric tensor of even order 2..=12 fitted to the ADCs.
    Tensor {
        /// The tensor's order (`--order`).
        order: u32,
    },
    /// Real SH of even bands 0..=`band` fitted to S/S0.
    Sh {
        /// The highest band, even (`--order`).
        band: u32,
        /// The basis the coefficients are written in (`--basis`).
        basis: ShBasis,
        /// DIPY's `legacy=True` variant of that basis.
        legacy: bool,
        /// Laplace-Beltrami weight (`--lambda`), 0 to [`MAX_LAMBDA`].
        lambda: f64,
    },
    /// A fibre ODF as real SH of even bands 0..=`band` (`odf`).
    Odf(OdfModel),
}

/// A fibre ODF as real SH of even bands 0..=`band` (`odf`). The methods other than CSD
/// ignore `tau` and `csd`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdfModel {
    /// How the ODF is computed (`--odf`: csa, qball, csd, msmt).
    pub method: OdfMethod,
    /// The highest band, even (`--order`).
    pub band: u32,
    /// The basis the coefficients are written in (`--basis`).
    pub basis: ShBasis,
    /// DIPY's `legacy=True` variant of that basis.
    pub legacy: bool,
    /// The Laplace-Beltrami weight of CSA and Q-ball; the constraint weight of CSD
    /// (`--lambda`).
    pub lambda: f64,
    /// CSD's threshold (`--tau`): DIPY's a fraction of the mean fODF, MRtrix's an
    /// absolute amplitude.
    pub tau: f64,
    /// Whose CSD algorithm runs (`--csd-algorithm`), which also says what `tau` means.
    pub csd: CsdAlgorithm,
}

impl FitModel {
    /// Checks the options on their own (before any file is read); errors name the
    /// [`Setting`].
    pub fn validate(&self) -> Result<()> {
        match *self {
            FitModel::Tensor { order } => {
                if !(2..=MAX_ORDER).contains(&order) || order % 2 == 1 {
                    return Err(Error::setting_value(
                        Setting::Order,
                        order,
                        format!(
                            "a diffusion tensor needs an even order from 2 to {MAX_ORDER} (the ADC profile is antipodally symmetric)"
                        ),
                    ));
                }
            }
            FitModel::Sh { band, lambda, .. } => {
                if band > MAX_ORDER || band % 2 == 1 {
                    return Err(Error::setting_value(
                        Setting::Order,
                        band,
                        format!(
                            "an SH fit needs an even band from 0 to {MAX_ORDER} (the signal is antipodally symmetric)"
                        ),
                    ));
                }
                check_lambda(lambda)?;
            }
            FitModel::Odf(odf) => {
                if odf.band > MAX_ORDER || odf.band % 2 == 1 {
                    return Err(Error::setting_value(
                        Setting::Order,
                        odf.band,
                        format!(
                            "an ODF needs an even band from 0 to {MAX_ORDER} (the ODF is antipodally symmetric)"
                        ),
                    ));
                }
                check_lambda(odf.lambda)?;
                check_tau(odf.tau, odf.csd)?;
            }
        }
        Ok(())
    }

    /// Coefficients per voxel: (n+1)(n+2)/2 for both models.
    pub fn coefficient_count(&self) -> usize {
        match *self {
            FitModel::Tensor { order } => glyphcast::glyph::monomials::symmetric_count(order),
            FitModel::Sh { band, .. } | FitModel::Odf(OdfModel { band, .. }) => sh_count(band),
        }
    }

    /// The glyph kind of the fitted coefficients: a symmetric tensor, or the SH series in
    /// its basis.
    pub fn glyph_kind(&self) -> GlyphKind {
        match *self {
            FitModel::Tensor { order } => GlyphKind::Tensor(glyphcast::glyph::TensorLayout {
                order,
                symmetry: glyphcast::glyph::Symmetry::Symmetric,
            }),
            FitModel::Sh {
                band,
                basis,
                legacy,
                ..
            }
            | FitModel::Odf(OdfModel {
                band,
                basis,
                legacy,
                ..
            }) => GlyphKind::Sh {
                band,
                basis,
                legacy,
            },
        }
    }

    /// A short description for the NIfTI header's `descrip` (at most 80 bytes).
    pub fn description(&self) -> String {
        match *self {
            FitModel::Tensor { order } => format!("{TENSOR_PREFIX}{order}"),
            FitModel::Sh {
                band,
                basis,
                legacy,
                lambda,
            } => {
                let basis = basis.name();
                let legacy = if legacy { " legacy" } else { "" };
                format!("glyphcast fit: SH band {band} {basis}{legacy} lambda {lambda}")
            }
            // The same start as `Sh`, so that `volume::recorded_basis` reads the basis.
            FitModel::Odf(odf) => {
                let (band, lambda) = (odf.band, odf.lambda);
                let basis = odf.basis.name();
                let legacy = if odf.legacy { " legacy" } else { "" };
                let (method, tau) = match (odf.method, odf.csd) {
                    (OdfMethod::Csd, CsdAlgorithm::Dipy) => ("csd", format!(" tau {}", odf.tau)),
                    // The threshold only when it is not dwi2fod's 0, so that the
                    // line fits the 80 bytes of a NIfTI description.
                    (OdfMethod::Csd, CsdAlgorithm::Mrtrix) if odf.tau == 0.0 => {
                        ("csd", " mrtrix".to_string())
                    }
                    (OdfMethod::Csd, CsdAlgorithm::Mrtrix) => {
                        ("csd", format!(" mrtrix threshold {}", odf.tau))
                    }
                    (method, _) => (method.name(), String::new()),
                };
                // Multi-tissue CSD has a hard constraint: no weight, no threshold.
                if method == "msmt" {
                    return format!("glyphcast fit: SH band {band} {basis}{legacy} msmt WM fODF");
                }
                format!(
                    "glyphcast fit: SH band {band} {basis}{legacy} {method} ODF lambda {lambda}{tau}"
                )
            }
        }
    }
}

/// The regularisation weight in 0 to [`MAX_LAMBDA`].
fn check_lambda(lambda: f64) -> Result<()> {
    if (0.0..=MAX_LAMBDA).contains(&lambda) {
        return Ok(());
    }
    Err(Error::setting_value(
        DmriSetting::Lambda,
        lambda,
        format!("the regularisation weight must be in 0 to {MAX_LAMBDA}"),
    ))
}

/// CSD's threshold: DIPY's a fraction of the mean fODF in 0 to 1, MRtrix's an absolute
/// amplitude in the range `dwi2fod -threshold` takes.
fn check_tau(tau: f64, csd: CsdAlgorithm) -> Result<()> {
    let (ok, why) = match csd {
        CsdAlgorithm::Dipy => (
            (0.0..1.0).contains(&tau),
            "DIPY's CSD threshold is a fraction of the mean fODF, in 0 to 1".to_string(),
        ),
        CsdAlgorithm::Mrtrix => {
            let range = csd_mrtrix::THRESHOLD_RANGE;
            (
                range.contains(&tau),
                format!(
                    "MRtrix's CSD threshold is an fODF amplitude, in {} to {} (as dwi2fod -threshold)",
                    range.start(),
                    range.end()
                ),
            )
        }
    };
    if ok {
        return Ok(());
    }
    Err(Error::setting_value(DmriSetting::Tau, tau, why))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::{commented_image, recorded_basis};

    /// What `fit` writes reads back as the basis it was fitted in.
    #[test]
    fn fit_descriptions_read_back() {
        for basis in ShBasis::ALL {
            for legacy in [false, true] {
                let model = FitModel::Sh {
                    band: 8,
                    basis,
                    legacy,
                    lambda: 0.006,
                };
                let recorded = recorded_basis(&commented_image(&model.description()))
                    .unwrap()
                    .unwrap();
                assert_eq!((recorded.basis, recorded.legacy), (basis, legacy));
                assert_eq!(recorded.field, "comments");
            }
        }
        let tensor = FitModel::Tensor { order: 4 }.description();
        assert_eq!(recorded_basis(&commented_image(&tensor)).unwrap(), None);
        // A basis glyphcast does not know is not read as some other one.
        let unknown = recorded_basis(&commented_image("glyphcast fit: SH band 8 fsl"));
        assert!(
            unknown.is_err_and(|e| e
                .to_string()
                .contains("comments: records the SH basis 'fsl'")),
            "an unknown basis is refused"
        );
    }
}
