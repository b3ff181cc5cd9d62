//! The tissue responses of multi-tissue CSD (`msmt`), one row per shell.
//!
//! - From files: MRtrix's multi-shell response format (`dwi2response dhollander` or
//!   `msmt_5tt`): one row per shell in increasing b, the b=0 shell first, each row the
//!   zonal SH coefficients r_0, r_2, ... (WM) or r_0 alone (GM, CSF); `#` comments. A
//!   `# Shells: 0,1000,...` comment, as MRtrix writes, is checked against the data's
//!   shells (within [`SHELL_GAP`]); the row count must equal the shell count. GM and CSF
//!   rows must be isotropic (coefficients past r_0 zero): their ODFs are band 0 here.
//! - Estimated from the data, as DIPY's `mask_for_response_msmt` and
//!   `response_from_mask_msmt` do, with disjoint tissue classes: a DTI fit on the lowest
//!   non-zero shell (the Gaussian model holds best there) in the central cube of
//!   [`RESPONSE_ROI_RADIUS`] voxels among the voxels that can only be tissue
//!   (`tissue`); white matter: FA above the WM threshold (0.7); grey matter: FA below
//!   [`ISO_FA`] and MD below [`GM_MAX_MD`]; CSF: FA below [`ISO_FA`] and MD above
//!   [`CSF_MIN_MD`] (DIPY's defaults overlap: its CSF class, MD < 3.2e-3, takes grey
//!   matter too). Per shell, WM's row is the response of the prolate tensor with the mean
//!   eigenvalues of a DTI fit to that shell alone (DIPY's per-shell tensors), GM's and
//!   CSF's r_0 = sqrt(4 pi) times the mean over the class of the shell's mean signal (an
//!   isotropic signal's whole band 0; DIPY takes exp(-b l1) of the tensor instead).
use std::path::Path;

use super::FitInputs;
use super::dti::DiffusionTensor;
use super::msmt::{SHELL_GAP, Shells, TissueResponses};
use super::response::{RESPONSE_ROI_RADIUS, Response, response_rows};
use super::tensor::TensorFitter;
use super::tissue::TissueMask;
use glyphcast::{Error, Result};

/// FA below which a voxel may be GM or CSF.
pub const ISO_FA: f64 = 0.2;
/// Grey matter: MD below this (mm^2/s).
pub const GM_MAX_MD: f64 = 1.1e-3;
/// CSF: MD above this (mm^2/s; free water at body temperature is about 3e-3).
pub const CSF_MIN_MD: f64 = 2.0e-3;

/// Reads the three response files for `shells` (errors name the file and the row).
pub fn read_responses(
    wm: &Path,
    gm: &Path,
    csf: &Path,
    shells: &Shells,
) -> Result<TissueResponses> {
    let wm = read_rows(wm, shells)?;
    let isotropic = |path: &Path| -> Result<Vec<f64>> {
        let rows = read_rows(path, shells)?;
        let file = path.display().to_string();
        rows.into_iter()
            .enumerate()
            .map(|(row, values)| {
                if let Some(v) = values.iter().skip(1).find(|v| **v != 0.0) {
                    return Err(Error::input(
                        &file,
                        format!("row {}", row + 1),
                        format!(
                            "a coefficient past l=0 ({v}): GM and CSF responses must be isotropic (one column), their ODFs are band 0"
                        ),
                    ));
                }
                Ok(values.first().copied().unwrap_or(0.0))
            })
            .collect()
    };
    Ok(TissueResponses {
        wm,
        gm: isotropic(gm)?,
        csf: isotropic(csf)?,
    })
}

/// One response file's rows, checked against the shells.
fn read_rows(path: &Path, shells: &Shells) -> Result<Vec<Vec<f64>>> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let rows = response_rows(&text, &file)?;
    if rows.len() != shells.len() {
        return Err(Error::input(
            &file,
            "rows",
            format!(
                "{} row(s) of coefficients, but the DWI has {} shells (b = {} s/mm^2): one row per shell, b=0 first, in increasing b",
                rows.len(),
                shells.len(),
                shells.list()
            ),
        ));
    }
    if let Some(listed) = listed_shells(&text) {
        if listed.len() != shells.len() {
            return Err(Error::input(
                &file,
                "Shells",
                format!(
                    "the file is for {} shells ({}), the DWI has {} (b = {})",
                    listed.len(),
                    listed
                        .iter()
                        .map(|b| format!("{b}"))
                        .collect::<Vec<_>>()
                        .join(", "),
                    shells.len(),
                    shells.list()
                ),
            ));
        }
        for (row, (b, data_b)) in listed.iter().zip(&shells.bvals).enumerate() {
            if (b - data_b).abs() > SHELL_GAP {
                return Err(Error::input(
                    &file,
                    format!("row {} (line {})", row + 1, rows[row].0),
                    format!(
                        "the file's row is for b = {b}, but shell {} of the DWI is at b = {data_b:.0} s/mm^2",
                        row + 1
                    ),
                ));
            }
        }
    }
    for (row, (line, values)) in rows.iter().enumerate() {
        let first = values.first().copied().unwrap_or(0.0);
        if first <= 0.0 {
            return Err(Error::input(
                &file,
                format!("row {} (line {line})", row + 1),
                format!("the l=0 coefficient must be positive, found {first}"),
            ));
        }
    }
    Ok(rows.into_iter().map(|(_, v)| v).collect())
}

/// The b-values of MRtrix's `# Shells: 0,1000,...` comment, if the file has one.
fn listed_shells(text: &str) -> Option<Vec<f64>> {
    text.lines().find_map(|line| {
        let rest = line
            .trim()
            .strip_prefix('#')?
            .trim()
            .strip_prefix("Shells:")?;
        rest.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .map(|w| w.parse::<f64>().ok())
            .collect()
    })
}

/// Responses estimated from the data, with what they came from.
#[derive(Clone, Debug)]
pub struct EstimatedResponses {
    /// The WM, GM and CSF responses, one row per shell.
    pub responses: TissueResponses,
    /// Voxels per tissue (WM, GM, CSF).
    pub voxels: [usize; 3],
    /// Each tissue's mean S0.
    pub s0: [f64; 3],
    /// The b-value of the shell the tissues were classified on.
    pub dti_shell: f64,
    /// Voxels that can only be tissue, in the central region.
    pub tissue_voxels: usize,
}

/// The per-voxel DTI on one shell: the tensor of the ADCs -ln(S/S0)/b.
struct ShellTensor {
    fitter: TensorFitter,
    volumes: Vec<(usize, f64)>,
}

impl ShellTensor {
    fn new(inputs: &FitInputs, shells: &Shells, shell: usize) -> Result<Self> {
        let mut volumes = Vec::new();
        let mut directions = Vec::new();
        for (v, d) in inputs.gradients.directions.iter().enumerate() {
            if let (Some(d), true) = (d, shells.of_volume[v] == shell) {
                volumes.push((v, inputs.gradients.bvals[v]));
                directions.push(*d);
            }
        }
        let fitter = TensorFitter::new(2, &directions).map_err(|e| {
            Error::input(
                &inputs.origin.directions,
                "directions",
                format!("the shell at b = {:.0}: {e}", shells.bvals[shell]),
            )
        })?;
        Ok(Self { fitter, volumes })
    }

    fn tensor(&self, series: &[f64], s0: f64) -> Option<DiffusionTensor> {
        let adc: Vec<f64> = self
            .volumes
            .iter()
            .map(|&(v, b)| -(series[v].max(1e-3 * s0) / s0).ln() / b)
            .collect();
        let mut coeffs = [0.0; 6];
        self.fitter.fit_into(&adc, &mut coeffs);
        DiffusionTensor::from_coefficients(&coeffs)
    }
}

/// Estimates the three tissues' responses up to `band` (see the module notes); Err,
/// naming the DWI, when a tissue has no voxel.
pub fn estimate_responses(
    inputs: &FitInputs,
    shells: &Shells,
    band: u32,
    wm_fa: f64,
) -> Result<EstimatedResponses> {
    let per_shell: Vec<ShellTensor> = (1..shells.len())
        .map(|s| ShellTensor::new(inputs, shells, s))
        .collect::<Result<_>>()?;
    let tissue = TissueMask::of(inputs);
    let shape = inputs.dwi.spatial_shape();
    let range = |axis: usize| {
        let centre = shape[axis] / 2;
        centre.saturating_sub(RESPONSE_ROI_RADIUS)
            ..(centre + RESPONSE_ROI_RADIUS + 1).min(shape[axis])
    };
    let b0 = inputs.gradients.b0_volumes();
    // Per tissue: voxel count, S0 sum; WM: per shell (l1, l2) sums; GM, CSF: per shell
    // sums of the shell mean.
    let mut count = [0usize; 3];
    let mut s0_sum = [0.0; 3];
    let mut wm_eigen = vec![(0.0, 0.0); shells.len()];
    let mut iso_mean = [vec![0.0; shells.len()], vec![0.0; shells.len()]];
    let mut tissue_voxels = 0;
    for z in range(2) {
        for y in range(1) {
            for x in range(0).filter(|&x| tissue.keep[[x, y, z]]) {
                tissue_voxels += 1;
                let series: Vec<f64> = inputs.dwi.signal.slice(ndarray::s![x, y, z, ..]).to_vec();
                if series.iter().any(|v| !v.is_finite()) {
                    continue;
                }
                let s0 = b0.iter().map(|&v| series[v]).sum::<f64>() / b0.len().max(1) as f64;
                let Some(dti) = per_shell[0].tensor(&series, s0) else {
                    continue;
                };
                let (fa, md) = (
                    dti.fractional_anisotropy(),
                    dti.eigenvalues.iter().sum::<f64>() / 3.0,
                );
                let class = if fa > wm_fa && dti.eigenvalues[2] > 0.0 {
                    0
                } else if fa < ISO_FA && md > 0.0 && md < GM_MAX_MD {
                    1
                } else if fa < ISO_FA && md > CSF_MIN_MD {
                    2
                } else {
                    continue;
                };
                count[class] += 1;
                s0_sum[class] += s0;
                if class == 0 {
                    for (s, fit) in per_shell.iter().enumerate() {
                        if let Some(t) = fit.tensor(&series, s0) {
                            wm_eigen[s + 1].0 += t.eigenvalues[0];
                            wm_eigen[s + 1].1 += t.eigenvalues[1];
                        }
                    }
                } else {
                    let mut sums = vec![(0.0, 0usize); shells.len()];
                    for (v, value) in series.iter().enumerate() {
                        let shell = shells.of_volume[v];
                        sums[shell].0 += value;
                        sums[shell].1 += 1;
                    }
                    for (acc, (sum, n)) in iso_mean[class - 1].iter_mut().zip(sums) {
                        *acc += sum / n.max(1) as f64;
                    }
                }
            }
        }
    }
    if let Some(missing) = (0..3).find(|&t| count[t] == 0) {
        let rule = match missing {
            0 => format!("FA above {wm_fa}"),
            1 => format!("FA below {ISO_FA} and MD below {GM_MAX_MD:e} mm^2/s"),
            _ => format!("FA below {ISO_FA} and MD above {CSF_MIN_MD:e} mm^2/s"),
        };
        return Err(Error::input(
            inputs.files.dwi.display().to_string(),
            "signal",
            format!(
                "no voxel for the {} response ({rule}, by DTI on the b = {:.0} shell) among the {tissue_voxels} tissue voxels of the central region: give the three response files",
                super::msmt::TISSUES[missing],
                shells.bvals[1]
            ),
        ));
    }
    let sqrt_4pi = (4.0 * std::f64::consts::PI).sqrt();
    let n = count.map(|c| c as f64);
    let wm_s0 = s0_sum[0] / n[0];
    let wm = (0..shells.len())
        .map(|s| {
            if s == 0 {
                let mut row = vec![0.0; band as usize / 2 + 1];
                row[0] = sqrt_4pi * wm_s0;
                return row;
            }
            let (l1, l2) = (wm_eigen[s].0 / n[0], wm_eigen[s].1 / n[0]);
            Response::from_tensor(l1, l2, wm_s0, shells.bvals[s], band).zonal
        })
        .collect();
    let iso = |t: usize| -> Vec<f64> {
        iso_mean[t]
            .iter()
            .map(|m| sqrt_4pi * m / n[t + 1])
            .collect()
    };
    Ok(EstimatedResponses {
        responses: TissueResponses {
            wm,
            gm: iso(0),
            csf: iso(1),
        },
        voxels: count,
        s0: [0, 1, 2].map(|t| s0_sum[t] / n[t]),
        dti_shell: shells.bvals[1],
        tissue_voxels,
    })
}
