//! The per-voxel work: normalise the signal by S0, fit, store. [`VoxelFitter`] holds
//! the model's solve (pseudo-inverse, regularised normal equations, an ODF transform or
//! CSD's deconvolution), prepared once for all voxels; [`fit`] runs it over the volume
//! on every core: worker threads take chunks of voxels in turn and send the results to
//! the calling thread, which stores them and reports progress.
use glam::DVec3;
use ndarray::{Array4, ArrayView1, s};
use std::sync::atomic::{AtomicUsize, Ordering};

use super::csd::{CsdFitter, CsdParameters, FIRST_ESTIMATE_BAND};
use super::csd_mrtrix::{CsdAlgorithm, MrtrixCsdFitter, MrtrixCsdParameters};
use super::odf::{LinearOdfFitter, OdfMethod};
use super::response::{DEFAULT_RESPONSE_FA, Response, estimate_response};
use super::sh::ShFitter;
use super::tensor::{TensorFitter, design_rank};
use super::{FitInputs, FitModel, OdfModel};
use crate::setting::DmriSetting;
use glyphcast::{Error, Result, Setting};

/// Samples at or below zero are raised to this fraction of S0 (see the module notes of
/// `fit`).
pub const SIGNAL_FLOOR: f64 = 1e-3;

/// The SH fit assumes one shell: diffusion-weighted b-values may differ by at most this
/// much (s/mm^2). Scanners spread a nominal shell by a few percent (small_64D: 988 to
/// 1001).
pub const SHELL_TOLERANCE: f64 = 100.0;

/// Voxels reported to the progress callback at a time.
const PROGRESS_CHUNK: u64 = 1024;

enum Solve {
    Tensor { fitter: TensorFitter },
    Sh { fitter: ShFitter },
    LinearOdf { fitter: LinearOdfFitter },
    Csd { fitter: Box<CsdFitter> },
    MrtrixCsd { fitter: Box<MrtrixCsdFitter> },
}

/// A model ready to be applied voxel by voxel, for one gradient table.
pub struct VoxelFitter {
    solve: Solve,
    b0: Vec<usize>,
    /// The diffusion-weighted volumes, with their b-values, in volume order.
    weighted: Vec<usize>,
    bvals: Vec<f64>,
}

/// Voxels of a fit that were left out (coefficients 0) or had samples raised to the
/// floor, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FitReport {
    /// Voxels visited (in the mask).
    pub visited: usize,
    /// Left out: a NaN or infinite sample.
    pub non_finite: usize,
    /// Left out: the mean b=0 signal is negative.
    pub negative_s0: usize,
    /// Left out: the mean b=0 signal is zero (background).
    pub zero_s0: usize,
    /// Fitted, with samples at or below zero raised to [`SIGNAL_FLOOR`] S0.
    pub floored: usize,
}

impl FitReport {
    /// Voxels that got coefficients.
    pub fn fitted(&self) -> usize {
        self.visited - self.non_finite - self.negative_s0 - self.zero_s0
    }

    fn count(&mut self, outcome: VoxelOutcome) {
        self.visited += 1;
        match outcome {
            VoxelOutcome::Fitted => {}
            VoxelOutcome::Floored => self.floored += 1,
            VoxelOutcome::NonFinite => self.non_finite += 1,
            VoxelOutcome::NegativeS0 => self.negative_s0 += 1,
            VoxelOutcome::ZeroS0 => self.zero_s0 += 1,
        }
    }

    /// Warnings for data that was changed or dropped without being background, one line
    /// each, naming `file` and the number of voxels.
    pub fn warnings(&self, file: &str) -> Vec<String> {
        let mut lines = Vec::new();
        if self.non_finite > 0 {
            lines.push(format!(
                "{file}: {} voxel(s) with NaN or infinite signal were set to 0",
                self.non_finite
            ));
        }
        if self.negative_s0 > 0 {
            lines.push(format!(
                "{file}: {} voxel(s) with a negative b=0 signal were set to 0",
                self.negative_s0
            ));
        }
        if self.floored > 0 {
            lines.push(format!(
                "{file}: {} voxel(s) had samples at or below 0, raised to {} of S0",
                self.floored, SIGNAL_FLOOR
            ));
        }
        lines
    }

    /// Err when no voxel could be fitted: the output would be all zeros. Names `file`
    /// and why the voxels were left out.
    pub(crate) fn check_any_fitted(&self, file: &str) -> Result<()> {
        if self.visited == 0 {
            return Err(Error::input(
                file,
                "mask",
                "the mask selects no voxel: nothing to fit",
            ));
        }
        if self.fitted() > 0 {
            return Ok(());
        }
        Err(Error::input(
            file,
            "signal",
            format!(
                "no voxel can be fitted ({} with NaN or infinite samples, {} with a negative and {} with a zero b=0 signal): the output would be all zeros",
                self.non_finite, self.negative_s0, self.zero_s0
            ),
        ))
    }
}

/// What became of one voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VoxelOutcome {
    /// Fitted from the samples as they are.
    Fitted,
    /// Fitted, with samples raised to the floor.
    Floored,
    /// Left at zero: a sample is NaN or infinite.
    NonFinite,
    /// Left at zero: the mean b=0 signal is negative.
    NegativeS0,
    /// Left at zero: the mean b=0 signal is exactly zero (S/S0 is undefined).
    ZeroS0,
}

impl VoxelOutcome {
    /// Whether the voxel got coefficients.
    pub fn is_fitted(self) -> bool {
        matches!(self, VoxelOutcome::Fitted | VoxelOutcome::Floored)
    }
}

/// Fits every voxel in the mask; returns [x, y, z, coefficient], zeros outside the
/// mask and in left-out voxels. `progress` is told how many voxels were done since its
/// last call. Err when no voxel can be fitted (see [`fit_with_report`]).
pub fn fit(
    inputs: &FitInputs,
    model: &FitModel,
    progress: &mut dyn FnMut(u64),
) -> Result<Array4<f64>> {
    fit_with_report(inputs, model, progress).map(|(coefficients, _)| coefficients)
}

/// [`fit`], with the count of voxels left out or floored. Err (naming the DWI, or the
/// mask when it selects nothing) when no voxel can be fitted: an all-NaN, all-zero or
/// negative series is an error, not an all-zero output.
pub fn fit_with_report(
    inputs: &FitInputs,
    model: &FitModel,
    progress: &mut dyn FnMut(u64),
) -> Result<(Array4<f64>, FitReport)> {
    fit_with_response(inputs, model, None, progress)
}

/// [`fit_with_report`], with CSD's single-fibre response given (`None`: estimated from
/// the data, `response::estimate_response` with its defaults). Other models ignore it.
pub fn fit_with_response(
    inputs: &FitInputs,
    model: &FitModel,
    response: Option<&Response>,
    progress: &mut dyn FnMut(u64),
) -> Result<(Array4<f64>, FitReport)> {
    let fitter = VoxelFitter::with_response(inputs, model, response)?;
    let [nx, ny, nz] = inputs.dwi.spatial_shape();
    let k = model.coefficient_count();
    let mut out = Array4::<f64>::zeros((nx, ny, nz, k));
    let voxels: Vec<[usize; 3]> = (0..nz)
        .flat_map(|z| (0..ny).flat_map(move |y| (0..nx).map(move |x| [x, y, z])))
        .filter(|&[x, y, z]| inputs.in_mask(x, y, z))
        .collect();
    let chunks: Vec<&[[usize; 3]]> = voxels.chunks(PROGRESS_CHUNK as usize).collect();
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .min(chunks.len().max(1));
    let mut report = FitReport::default();
    std::thread::scope(|scope| {
        let (sender, receiver) = std::sync::mpsc::channel();
        for _ in 0..threads {
            let sender = sender.clone();
            let (fitter, chunks, next) = (&fitter, &chunks, &next);
            scope.spawn(move || {
                let mut scratch = vec![0.0; fitter.weighted.len()];
                loop {
                    let index = next.fetch_add(1, Ordering::Relaxed);
                    let Some(chunk) = chunks.get(index) else {
                        break;
                    };
                    let mut coeffs = vec![0.0; chunk.len() * k];
                    let outcomes: Vec<VoxelOutcome> = chunk
                        .iter()
                        .zip(coeffs.chunks_mut(k))
                        .map(|(&[x, y, z], c)| {
                            let series = inputs.dwi.signal.slice(s![x, y, z, ..]);
                            fitter.fit_voxel(series, &mut scratch, c)
                        })
                        .collect();
                    if sender.send((index, coeffs, outcomes)).is_err() {
                        break;
                    }
                }
            });
        }
        drop(sender);
        for (index, coeffs, outcomes) in receiver {
            for ((&[x, y, z], c), outcome) in
                chunks[index].iter().zip(coeffs.chunks(k)).zip(outcomes)
            {
                out.slice_mut(s![x, y, z, ..])
                    .iter_mut()
                    .zip(c)
                    .for_each(|(o, v)| *o = *v);
                report.count(outcome);
            }
            progress(chunks[index].len() as u64);
        }
    });
    let culprit = match (&inputs.files.mask, report.visited) {
        (Some(mask), 0) => mask.display().to_string(),
        _ => inputs.files.dwi.display().to_string(),
    };
    report.check_any_fitted(&culprit)?;
    Ok((out, report))
}

impl VoxelFitter {
    /// Builds the model's solve for the inputs' directions; errors name the bvec or bval
    /// file.
    pub fn new(inputs: &FitInputs, model: &FitModel) -> Result<Self> {
        Self::with_response(inputs, model, None)
    }

    /// [`VoxelFitter::new`] with CSD's response given (`None`: estimated from the data).
    pub fn with_response(
        inputs: &FitInputs,
        model: &FitModel,
        response: Option<&Response>,
    ) -> Result<Self> {
        model.validate()?;
        let table = inputs.gradients.weighted();
        let directions: Vec<DVec3> = table.iter().map(|w| w.2).collect();
        let bvals: Vec<f64> = table.iter().map(|w| w.1).collect();
        let bvec_file = inputs.origin.directions.clone();
        // CSD may ask for more coefficients than there are directions: the constraint
        // determines the rest (super-resolved CSD, Tournier et al. 2007, as dwi2fod -lmax
        // does); the directions must then determine the bands of its first estimate.
        let super_resolved = matches!(
            model,
            FitModel::Odf(OdfModel {
                method: OdfMethod::Csd,
                ..
            })
        );
        let unknowns = match *model {
            FitModel::Odf(OdfModel { band, .. }) if super_resolved => {
                super::sh::sh_count(band.min(FIRST_ESTIMATE_BAND))
            }
            _ => model.coefficient_count(),
        };
        if directions.len() < unknowns {
            return Err(Error::input(
                bvec_file,
                "directions",
                glyphcast::message![
                    format!(
                        "{} diffusion-weighted directions cannot determine the {unknowns} coefficients of the fit (",
                        directions.len()
                    ),
                    Setting::Order,
                    " too high)"
                ],
            ));
        }
        // The directions' problems name the b-vector file; a refused setting stays one.
        let to_input = |e: Error| match e {
            Error::Setting { .. } => e,
            e => Error::input(&bvec_file, "directions", e.to_string()),
        };
        let solve = match *model {
            FitModel::Tensor { order } => Solve::Tensor {
                fitter: TensorFitter::new(order, &directions).map_err(to_input)?,
            },
            FitModel::Sh {
                band,
                basis,
                legacy,
                lambda,
            } => {
                check_single_shell(&bvals, &inputs.origin.bvals, "the SH fit")?;
                check_sh_directions(band, &directions, &bvec_file)?;
                Solve::Sh {
                    fitter: ShFitter::new(band, basis, legacy, &directions, lambda)
                        .map_err(to_input)?,
                }
            }
            FitModel::Odf(odf) => {
                let what = match odf.method {
                    OdfMethod::Msmt => {
                        return Err(Error::Call {
                            call: "VoxelFitter::new",
                            expected: "a model fitted voxel by voxel (multi-tissue CSD is \
                                       fitted by fit::msmt::fit_msmt)",
                        });
                    }
                    OdfMethod::Csd => "single-shell CSD",
                    OdfMethod::Csa => "the CSA ODF",
                    OdfMethod::Qball => "the Q-ball ODF",
                };
                check_single_shell(&bvals, &inputs.origin.bvals, what)?;
                let determined = if odf.method == OdfMethod::Csd {
                    determined_band(odf.band, directions.len())
                } else {
                    odf.band
                };
                check_sh_directions(determined, &directions, &bvec_file)?;
                if odf.method == OdfMethod::Csd {
                    let estimated;
                    let response = match response {
                        Some(r) => r,
                        None => {
                            estimated =
                                estimate_response(inputs, odf.band, DEFAULT_RESPONSE_FA)?.response;
                            &estimated
                        }
                    };
                    match odf.csd {
                        CsdAlgorithm::Dipy => Solve::Csd {
                            fitter: Box::new(
                                CsdFitter::new(
                                    odf.band,
                                    (odf.basis, odf.legacy),
                                    &directions,
                                    response,
                                    CsdParameters {
                                        lambda: odf.lambda,
                                        tau: odf.tau,
                                    },
                                )
                                .map_err(to_input)?,
                            ),
                        },
                        CsdAlgorithm::Mrtrix => {
                            let parameters = MrtrixCsdParameters {
                                neg_lambda: odf.lambda,
                                threshold: odf.tau,
                                ..MrtrixCsdParameters::default()
                            };
                            Solve::MrtrixCsd {
                                fitter: Box::new(
                                    MrtrixCsdFitter::new(
                                        odf.band,
                                        (odf.basis, odf.legacy),
                                        &directions,
                                        response,
                                        parameters,
                                    )
                                    .map_err(to_input)?,
                                ),
                            }
                        }
                    }
                } else {
                    Solve::LinearOdf {
                        fitter: LinearOdfFitter::new(
                            odf.method,
                            odf.band,
                            (odf.basis, odf.legacy),
                            &directions,
                            odf.lambda,
                        )
                        .map_err(to_input)?,
                    }
                }
            }
        };
        Ok(Self {
            solve,
            b0: inputs.gradients.b0_volumes(),
            weighted: table.iter().map(|w| w.0).collect(),
            bvals,
        })
    }

    /// Fits one voxel's series (all volumes) into `coeffs`; `scratch` holds one value
    /// per weighted volume. A left-out voxel gets zeros.
    pub fn fit_voxel(
        &self,
        series: ArrayView1<f64>,
        scratch: &mut [f64],
        coeffs: &mut [f64],
    ) -> VoxelOutcome {
        let (outcome, s0) = self.normalise(series, scratch);
        if !outcome.is_fitted() {
            coeffs.iter_mut().for_each(|c| *c = 0.0);
            return outcome;
        }
        match &self.solve {
            Solve::Tensor { fitter } => {
                // ADC_i = -ln(S_i / S0) / b_i (Stejskal-Tanner), in place.
                scratch
                    .iter_mut()
                    .zip(&self.bvals)
                    .for_each(|(r, b)| *r = -r.ln() / b);
                fitter.fit_into(scratch, coeffs);
            }
            Solve::Sh { fitter } => coeffs.copy_from_slice(&fitter.fit(scratch)),
            Solve::LinearOdf { fitter } => fitter.fit_into(scratch, coeffs),
            Solve::Csd { fitter } => {
                // CSD deconvolves the signal in the response's units.
                scratch.iter_mut().for_each(|r| *r *= s0);
                fitter.fit_into(scratch, coeffs);
            }
            Solve::MrtrixCsd { fitter } => {
                scratch.iter_mut().for_each(|r| *r *= s0);
                fitter.fit_into(scratch, coeffs);
            }
        }
        outcome
    }

    /// The model's S/S0 at the weighted volumes (volume order) for `coeffs`:
    /// exp(-b_i D(g_i)) for a tensor, the SH series for SH; `None` for an ODF, which is
    /// not a signal.
    pub fn fitted_signal(&self, coeffs: &[f64]) -> Option<Vec<f64>> {
        Some(match &self.solve {
            Solve::Tensor { fitter } => fitter
                .fitted_values(coeffs)
                .iter()
                .zip(&self.bvals)
                .map(|(d, b)| (-b * d).exp())
                .collect(),
            Solve::Sh { fitter } => fitter.fitted_values(coeffs),
            Solve::LinearOdf { .. } | Solve::Csd { .. } | Solve::MrtrixCsd { .. } => return None,
        })
    }

    /// S_i / S0 for the weighted volumes into `ratio`, with samples at or below zero
    /// raised to SIGNAL_FLOOR S0. The voxel is left out if S0 <= 0 or a sample is not
    /// finite.
    pub fn normalised_signal(&self, series: ArrayView1<f64>, ratio: &mut [f64]) -> VoxelOutcome {
        self.normalise(series, ratio).0
    }

    /// [`VoxelFitter::normalised_signal`], with S0.
    fn normalise(&self, series: ArrayView1<f64>, ratio: &mut [f64]) -> (VoxelOutcome, f64) {
        if self
            .b0
            .iter()
            .chain(&self.weighted)
            .any(|&v| !series[v].is_finite())
        {
            return (VoxelOutcome::NonFinite, 0.0);
        }
        let s0 = self.b0.iter().map(|&v| series[v]).sum::<f64>() / self.b0.len() as f64;
        if s0 < 0.0 {
            return (VoxelOutcome::NegativeS0, s0);
        }
        if s0 <= 0.0 {
            return (VoxelOutcome::ZeroS0, s0);
        }
        let mut outcome = VoxelOutcome::Fitted;
        for (r, &v) in ratio.iter_mut().zip(&self.weighted) {
            let s = series[v];
            if s <= SIGNAL_FLOOR * s0 {
                outcome = VoxelOutcome::Floored;
            }
            *r = s.max(SIGNAL_FLOOR * s0) / s0;
        }
        (outcome, s0)
    }

    /// Number of diffusion-weighted volumes.
    pub fn weighted_count(&self) -> usize {
        self.weighted.len()
    }
}

/// The SH fit's regularisation makes even identical directions solvable, with the
/// penalty alone choosing the coefficients; refused here as the tensor fit refuses them,
/// by the rank of the unregularised design (`tensor::design_rank`).
/// The highest even band up to `band` whose SH series `count` directions can determine.
fn determined_band(band: u32, count: usize) -> u32 {
    (0..=band)
        .step_by(2)
        .filter(|&b| super::sh::sh_count(b) <= count)
        .max()
        .unwrap_or(0)
}

fn check_sh_directions(band: u32, directions: &[DVec3], bvec_file: &str) -> Result<()> {
    let unknowns = super::sh::sh_count(band);
    let rank = design_rank(band, directions);
    if rank < unknowns {
        return Err(Error::input(
            bvec_file,
            "directions",
            format!(
                "the {} directions determine only {rank} of the {unknowns} coefficients of an SH series of band {band} (repeated directions, or all on one great circle?)",
                directions.len()
            ),
        ));
    }
    Ok(())
}

/// Err unless the weighted b-values form one shell; `what` names the model in the error.
fn check_single_shell(bvals: &[f64], bval_file: &str, what: &str) -> Result<()> {
    let (low, high) = bvals.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &b| {
        (lo.min(b), hi.max(b))
    });
    if high - low > SHELL_TOLERANCE {
        let text = format!(
            "{what} needs one shell, but the diffusion-weighted b-values range from {low} to \
             {high} s/mm^2 (multi-shell data)"
        );
        return Err(Error::input(
            bval_file,
            "b-values",
            if what == "single-shell CSD" {
                glyphcast::message![
                    text,
                    ": fit it with ",
                    DmriSetting::Odf.with("msmt"),
                    " (multi-shell multi-tissue CSD)"
                ]
            } else {
                text.into()
            },
        ));
    }
    Ok(())
}
