//! The per-voxel work: normalise the signal by S0, fit, store. [`VoxelFitter`] holds
//! the model's solve (pseudo-inverse or regularised normal equations), prepared once for
//! all voxels; [`fit`] runs it over the volume.
use glam::DVec3;
use ndarray::{Array4, ArrayView1, s};

use super::sh::ShFitter;
use super::tensor::TensorFitter;
use super::{FitInputs, FitModel};
use crate::{Error, Result};

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
}

/// A model ready to be applied voxel by voxel, for one gradient table.
pub struct VoxelFitter {
    solve: Solve,
    b0: Vec<usize>,
    /// The diffusion-weighted volumes, with their b-values, in volume order.
    weighted: Vec<usize>,
    bvals: Vec<f64>,
}

/// Fits every voxel in the mask; returns [x, y, z, coefficient], zeros outside the
/// mask and in left-out voxels. `progress` is told how many voxels were done since its
/// last call.
pub fn fit(
    inputs: &FitInputs,
    model: &FitModel,
    progress: &mut dyn FnMut(u64),
) -> Result<Array4<f64>> {
    let fitter = VoxelFitter::new(inputs, model)?;
    let [nx, ny, nz] = inputs.dwi.spatial_shape();
    let mut out = Array4::<f64>::zeros((nx, ny, nz, model.coefficient_count()));
    let mut scratch = vec![0.0; fitter.weighted.len()];
    let mut pending = 0;
    for z in 0..nz {
        for y in 0..ny {
            for x in (0..nx).filter(|&x| inputs.in_mask(x, y, z)) {
                let series = inputs.dwi.signal.slice(s![x, y, z, ..]);
                let mut coeffs = out.slice_mut(s![x, y, z, ..]);
                if let Some(coeffs) = coeffs.as_slice_mut() {
                    fitter.fit_voxel(series, &mut scratch, coeffs);
                } else {
                    let mut buffer = coeffs.to_vec();
                    fitter.fit_voxel(series, &mut scratch, &mut buffer);
                    coeffs.iter_mut().zip(buffer).for_each(|(o, c)| *o = c);
                }
                pending += 1;
                if pending == PROGRESS_CHUNK {
                    progress(pending);
                    pending = 0;
                }
            }
        }
    }
    progress(pending);
    Ok(out)
}

impl VoxelFitter {
    /// Builds the model's solve for the inputs' directions; errors name the bvec or bval
    /// file.
    pub fn new(inputs: &FitInputs, model: &FitModel) -> Result<Self> {
        model.validate()?;
        let table = inputs.gradients.weighted();
        let directions: Vec<DVec3> = table.iter().map(|w| w.2).collect();
        let bvals: Vec<f64> = table.iter().map(|w| w.1).collect();
        let bvec_file = inputs.origin.directions.clone();
        let unknowns = model.coefficient_count();
        if directions.len() < unknowns {
            return Err(Error::input(
                bvec_file,
                "directions",
                format!(
                    "{} diffusion-weighted directions cannot determine the {unknowns} coefficients of the fit (--order too high)",
                    directions.len()
                ),
            ));
        }
        let to_input = |e: Error| Error::input(&bvec_file, "directions", e.to_string());
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
                check_single_shell(&bvals, &inputs.origin.bvals)?;
                Solve::Sh {
                    fitter: ShFitter::new(band, basis, legacy, &directions, lambda)
                        .map_err(to_input)?,
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
    /// per weighted volume. A left-out voxel gets zeros and `false`.
    pub fn fit_voxel(
        &self,
        series: ArrayView1<f64>,
        scratch: &mut [f64],
        coeffs: &mut [f64],
    ) -> bool {
        if !self.normalised_signal(series, scratch) {
            coeffs.iter_mut().for_each(|c| *c = 0.0);
            return false;
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
        }
        true
    }

    /// The model's S/S0 at the weighted volumes (volume order) for `coeffs`:
    /// exp(-b_i D(g_i)) for a tensor, the SH series for SH.
    pub fn fitted_signal(&self, coeffs: &[f64]) -> Vec<f64> {
        match &self.solve {
            Solve::Tensor { fitter } => fitter
                .fitted_values(coeffs)
                .iter()
                .zip(&self.bvals)
                .map(|(d, b)| (-b * d).exp())
                .collect(),
            Solve::Sh { fitter } => fitter.fitted_values(coeffs),
        }
    }

    /// S_i / S0 for the weighted volumes into `ratio`, with samples at or below zero
    /// raised to SIGNAL_FLOOR S0. False (voxel left out) if S0 <= 0 or a sample is not
    /// finite.
    pub fn normalised_signal(&self, series: ArrayView1<f64>, ratio: &mut [f64]) -> bool {
        let s0 = self.b0.iter().map(|&v| series[v]).sum::<f64>() / self.b0.len() as f64;
        if !(s0.is_finite() && s0 > 0.0) {
            return false;
        }
        for (r, &v) in ratio.iter_mut().zip(&self.weighted) {
            let s = series[v];
            if !s.is_finite() {
                return false;
            }
            *r = s.max(SIGNAL_FLOOR * s0) / s0;
        }
        true
    }

    /// Number of diffusion-weighted volumes.
    pub fn weighted_count(&self) -> usize {
        self.weighted.len()
    }
}

fn check_single_shell(bvals: &[f64], bval_file: &str) -> Result<()> {
    let (low, high) = bvals.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &b| {
        (lo.min(b), hi.max(b))
    });
    if high - low > SHELL_TOLERANCE {
        return Err(Error::input(
            bval_file,
            "b-values",
            format!(
                "the SH fit needs one shell, but the diffusion-weighted b-values range from {low} to {high} s/mm^2"
            ),
        ));
    }
    Ok(())
}
