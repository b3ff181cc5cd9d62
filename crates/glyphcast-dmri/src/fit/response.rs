//! CSD's single-fibre response: the signal of one fibre along z, as the zonal (m = 0)
//! coefficients r_l of its orthonormal SH series, l = 0, 2, ..., in signal units.
//!
//! - From a file: MRtrix's text format (`dwi2response` output): one row of r_l per
//!   shell, numbers separated by spaces or commas, `#` comment lines. Single-shell CSD
//!   takes exactly one row.
//! - Estimated from the data, as DIPY's `auto_response_ssst` does: a DTI fit in the
//!   voxels of a cube of radius 10 voxels around the centre of the volume that can only
//!   be tissue (in the mask if one is given, and above the b=0 image's background
//!   threshold if it has a background: `tissue`), the voxels with FA above a threshold (0.7), and a prolate tensor with their
//!   mean largest and mean second eigenvalue and their mean S0. Its signal
//!   S0 exp(-b (l2 + (l1 - l2) z^2)) at the shell's mean b-value is projected onto
//!   Y_l^0 by quadrature: r_l = 2 pi int_-1^1 S(z) Y_l^0(z) dz.
use std::path::Path;

use super::basis::legendre;
use super::dti::DiffusionTensor;
use super::tissue::TissueMask;
use super::{FitInputs, FitModel, VoxelFitter};
use crate::setting::DmriSetting;
use glyphcast::{Error, Result};

/// Default FA threshold for the voxels of the response estimate (DIPY's).
pub const DEFAULT_RESPONSE_FA: f64 = 0.7;

/// Half the side of the central cube the response is estimated in (voxels; DIPY's
/// `roi_radii`).
pub const RESPONSE_ROI_RADIUS: usize = 10;

/// Intervals of the composite Simpson rule that projects the response onto Y_l^0; the
/// integrand is smooth, so the error is far below the float32 of the output.
const QUADRATURE_INTERVALS: usize = 2000;

/// A single-fibre response: zonal SH coefficients r_0, r_2, ... (orthonormal basis,
/// axis along z).
#[derive(Clone, Debug, PartialEq)]
pub struct Response {
    /// r_l for l = 0, 2, 4, ...
    pub zonal: Vec<f64>,
}

/// A response estimated from the data, with what it was estimated from.
#[derive(Clone, Debug, PartialEq)]
pub struct ResponseEstimate {
    /// The response, up to the requested band.
    pub response: Response,
    /// Mean eigenvalues (l1, l2, l2) of the selected voxels (mm^2/s for b in s/mm^2).
    pub eigenvalues: [f64; 3],
    /// Their mean S0.
    pub s0: f64,
    /// How many voxels were averaged.
    pub voxels: usize,
    /// The smallest and largest S0 among them.
    pub s0_range: (f64, f64),
    /// Their bounding box: per voxel axis the first and last index.
    pub bounds: [[usize; 2]; 3],
    /// The tissue threshold on S0 they were chosen above (Otsu's, `tissue`), when the
    /// volume has a background; and how many voxels the tissue mask keeps.
    pub threshold: Option<f64>,
    /// Voxels above `threshold` (every voxel of the mask without one).
    pub tissue_voxels: usize,
}

impl Response {
    /// The response of a prolate tensor with eigenvalues (`parallel`, `perpendicular`,
    /// `perpendicular`) and b=0 signal `s0`, at b-value `b`, up to band `band`.
    pub fn from_tensor(parallel: f64, perpendicular: f64, s0: f64, b: f64, band: u32) -> Self {
        let signal =
            |z: f64| s0 * (-b * (perpendicular + (parallel - perpendicular) * z * z)).exp();
        let zonal = (0..=band)
            .step_by(2)
            .map(|l| {
                let norm = ((2.0 * f64::from(l) + 1.0) / (4.0 * std::f64::consts::PI)).sqrt();
                let integrand = |z: f64| signal(z) * norm * legendre(l, z);
                2.0 * std::f64::consts::PI * simpson(integrand, -1.0, 1.0)
            })
            .collect();
        Self { zonal }
    }

    /// Reads MRtrix's response format from `path`; errors name the file and the line.
    pub fn read(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        let rows = response_rows(&text, &file)?;
        match rows.as_slice() {
            [] => Err(Error::input(
                &file,
                "response",
                "the file holds no coefficients",
            )),
            [(line, zonal)] => {
                let first = zonal.first().copied().unwrap_or(0.0);
                if first <= 0.0 {
                    return Err(Error::input(
                        &file,
                        format!("line {line}"),
                        format!("the l=0 coefficient must be positive, found {first}"),
                    ));
                }
                Ok(Self {
                    zonal: zonal.clone(),
                })
            }
            [_, (line, _), ..] => Err(Error::input(
                &file,
                format!("line {line}"),
                glyphcast::message![
                    format!(
                        "{} rows of coefficients: a multi-shell response, but CSD here is single-shell (one row); multi-shell data is fitted with ",
                        rows.len()
                    ),
                    DmriSetting::Odf.with("msmt")
                ],
            )),
        }
    }

    /// The highest band the response gives.
    pub fn band(&self) -> u32 {
        2 * (self.zonal.len() as u32).saturating_sub(1)
    }

    /// The convolution factor of band l: sqrt(4 pi / (2l+1)) r_l (Funk-Hecke), 0 past
    /// the response's last band.
    pub fn convolution_factor(&self, l: u32) -> f64 {
        let r = self.zonal.get(l as usize / 2).copied().unwrap_or(0.0);
        (4.0 * std::f64::consts::PI / (2.0 * f64::from(l) + 1.0)).sqrt() * r
    }

    /// The response written in MRtrix's format (one row).
    pub fn to_text(&self) -> String {
        let row: Vec<String> = self.zonal.iter().map(|v| format!("{v}")).collect();
        format!("{}\n", row.join(" "))
    }
}

/// The rows of numbers of MRtrix's response format in `text` (of `file`), each with its
/// line number; blank and `#` lines skipped. Errors name the file and the line.
pub(crate) fn response_rows(text: &str, file: &str) -> Result<Vec<(usize, Vec<f64>)>> {
    let mut rows: Vec<(usize, Vec<f64>)> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let values = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|w| !w.is_empty())
            .map(|w| {
                w.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        Error::input(
                            file,
                            format!("line {}", number + 1),
                            format!("{} is not a finite number", glyphcast::error::quoted(w)),
                        )
                    })
            })
            .collect::<Result<Vec<f64>>>()?;
        rows.push((number + 1, values));
    }
    Ok(rows)
}

fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    let n = QUADRATURE_INTERVALS;
    let h = (b - a) / n as f64;
    let inner: f64 = (1..n)
        .map(|i| {
            let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
            weight * f(a + i as f64 * h)
        })
        .sum();
    (f(a) + f(b) + inner) * h / 3.0
}

/// Estimates the response from `inputs` (see the module notes), up to band `band`.
/// Err, naming the DWI, when no voxel of the central region has FA above
/// `fa_threshold`.
pub fn estimate_response(
    inputs: &FitInputs,
    band: u32,
    fa_threshold: f64,
) -> Result<ResponseEstimate> {
    let dti = VoxelFitter::new(inputs, &FitModel::Tensor { order: 2 })?;
    let shape = inputs.dwi.spatial_shape();
    let range = |axis: usize| {
        let centre = shape[axis] / 2;
        centre.saturating_sub(RESPONSE_ROI_RADIUS)
            ..(centre + RESPONSE_ROI_RADIUS + 1).min(shape[axis])
    };
    let tissue = TissueMask::of(inputs);
    let mut scratch = vec![0.0; dti.weighted_count()];
    let mut coeffs = [0.0; 6];
    let (mut sum_l1, mut sum_l2, mut sum_s0, mut count) = (0.0, 0.0, 0.0, 0usize);
    let mut s0_range = (f64::INFINITY, f64::NEG_INFINITY);
    let mut bounds = [[usize::MAX, 0]; 3];
    for z in range(2) {
        for y in range(1) {
            for x in range(0).filter(|&x| tissue.keep[[x, y, z]]) {
                let series = inputs.dwi.signal.slice(ndarray::s![x, y, z, ..]);
                if !dti.fit_voxel(series, &mut scratch, &mut coeffs).is_fitted() {
                    continue;
                }
                let Some(tensor) = DiffusionTensor::from_coefficients(&coeffs) else {
                    continue;
                };
                if tensor.eigenvalues[2] <= 0.0 || tensor.fractional_anisotropy() <= fa_threshold {
                    continue;
                }
                sum_l1 += tensor.eigenvalues[0];
                sum_l2 += tensor.eigenvalues[1];
                let s0 = tissue.s0[[x, y, z]];
                sum_s0 += s0;
                s0_range = (s0_range.0.min(s0), s0_range.1.max(s0));
                for (bound, index) in bounds.iter_mut().zip([x, y, z]) {
                    *bound = [bound[0].min(index), bound[1].max(index)];
                }
                count += 1;
            }
        }
    }
    if count == 0 {
        let side = |axis: usize| range(axis).len();
        return Err(Error::input(
            inputs.files.dwi.display().to_string(),
            "signal",
            glyphcast::message![
                format!(
                    "no tissue voxel of the central {}x{}x{} region{} has FA above {fa_threshold}, so no single-fibre response can be estimated: give ",
                    side(0),
                    side(1),
                    side(2),
                    match (inputs.mask.is_some(), tissue.threshold) {
                        (true, _) => " (in the mask)".to_string(),
                        (false, Some(t)) =>
                            format!(" (S0 above {t:.1}, Otsu's threshold of the b=0 image)"),
                        (false, None) => String::new(),
                    }
                ),
                DmriSetting::Response.with("FILE"),
                ", or a lower ",
                DmriSetting::ResponseFa
            ],
        ));
    }
    let n = count as f64;
    let (l1, l2, s0) = (sum_l1 / n, sum_l2 / n, sum_s0 / n);
    let weighted = inputs.gradients.weighted();
    let b = weighted.iter().map(|w| w.1).sum::<f64>() / weighted.len().max(1) as f64;
    Ok(ResponseEstimate {
        response: Response::from_tensor(l1, l2, s0, b, band),
        eigenvalues: [l1, l2, l2],
        s0,
        voxels: count,
        s0_range,
        bounds,
        threshold: tissue.threshold,
        tissue_voxels: tissue.count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isotropic_response_is_only_band_zero() {
        // S = s0 exp(-b d) everywhere: r_0 = sqrt(4 pi) S, every other band 0.
        let r = Response::from_tensor(1e-3, 1e-3, 100.0, 1000.0, 8);
        let expected = (4.0 * std::f64::consts::PI).sqrt() * 100.0 * (-1.0f64).exp();
        assert!((r.zonal[0] - expected).abs() < 1e-9 * expected);
        assert!(
            r.zonal[1..].iter().all(|v| v.abs() < 1e-9 * expected),
            "{:?}",
            r.zonal
        );
        // A fibre along z: the signal is low along z, so r_2 < 0, and bands alternate.
        let fibre = Response::from_tensor(1.7e-3, 0.3e-3, 100.0, 1000.0, 8);
        assert!(fibre.zonal[1] < 0.0 && fibre.zonal[2] > 0.0 && fibre.zonal[3] < 0.0);
        assert_eq!(fibre.band(), 8);
    }

    #[test]
    fn reads_mrtrix_response_files() {
        let dir = std::env::temp_dir().join(format!("glyphcast-response-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("wm.txt");
        std::fs::write(&file, "# Shells: 1000\n 512.5 -200.25 50 -8.5\n").unwrap();
        let r = Response::read(&file).unwrap();
        assert_eq!(r.zonal, vec![512.5, -200.25, 50.0, -8.5]);
        assert_eq!(
            Response::read(&file).unwrap().to_text(),
            "512.5 -200.25 50 -8.5\n"
        );
        std::fs::write(&file, "500 -200 50\n600 -100 20\n").unwrap();
        let err = Response::read(&file).unwrap_err().to_string();
        assert!(
            err.contains("multi-shell") && err.contains("wm.txt"),
            "{err}"
        );
        std::fs::write(&file, "500 abc\n").unwrap();
        let err = Response::read(&file).unwrap_err().to_string();
        assert!(err.contains("line 1") && err.contains("abc"), "{err}");
        std::fs::write(&file, ",,\n").unwrap();
        let err = Response::read(&file).unwrap_err().to_string();
        assert!(err.contains("l=0"), "{err}");
        std::fs::write(&file, "# nothing\n").unwrap();
        assert!(Response::read(&file).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
