//! Which voxels of a DWI can only be tissue: the b=0 image (S0) split by Otsu's
//! threshold, as DIPY's `median_otsu` splits its smoothed b=0 image (without the median
//! filter, and on ln S0: the threshold is only asked to separate the air around a head,
//! whose S0 is a few percent of tissue's, from the head; in linear units a large class of
//! air is lumped with tissue and split from CSF).
//!
//! Inside a head the b=0 image is bimodal too (CSF is bright, white matter darker), and
//! Otsu's threshold would then cut white matter away. So the split is taken as a
//! background only when its darker class is dark: a mean below [`BACKGROUND_RATIO`]
//! times the brighter class's. A volume cropped to the brain has no such class (DIPY's
//! small_64D: tissue against CSF, 230 against 1120, a ratio of 0.21), and every voxel
//! with S0 > 0 counts as tissue; air around a head (S0 about 10 to 30 against tissue's
//! 300 and more) is below 0.1.
use ndarray::{Array3, s};

use super::FitInputs;

/// The darker class of Otsu's split is background when its mean S0 is below this
/// fraction of the brighter class's (air: a few percent of tissue; tissue against CSF:
/// a fifth or more).
pub const BACKGROUND_RATIO: f64 = 0.1;

/// Histogram bins of Otsu's threshold.
const BINS: usize = 256;

/// The tissue mask of a DWI and how it was made.
#[derive(Clone, Debug)]
pub struct TissueMask {
    /// Per voxel: S0 > 0 and finite, above the background threshold if any, and in the
    /// user's mask if one was given.
    pub keep: Array3<bool>,
    /// Each voxel's S0 (mean of the b=0 volumes).
    pub s0: Array3<f64>,
    /// Otsu's threshold, when the volume has a background it separates.
    pub threshold: Option<f64>,
}

impl TissueMask {
    /// The tissue of `inputs` (see the module notes).
    pub fn of(inputs: &FitInputs) -> Self {
        let b0 = inputs.gradients.b0_volumes();
        let [nx, ny, nz] = inputs.dwi.spatial_shape();
        let s0 = Array3::from_shape_fn((nx, ny, nz), |(x, y, z)| {
            let series = inputs.dwi.signal.slice(s![x, y, z, ..]);
            b0.iter().map(|&v| series[v]).sum::<f64>() / b0.len().max(1) as f64
        });
        let positive: Vec<f64> = s0
            .iter()
            .copied()
            .filter(|v| v.is_finite() && *v > 0.0)
            .collect();
        // Otsu on ln S0: air, tissue and CSF are then classes of similar spread, and a
        // large class of air is split from the head rather than from CSF.
        let logs: Vec<f64> = positive.iter().map(|v| v.ln()).collect();
        let threshold = otsu_threshold(&logs).map(f64::exp).filter(|&t| {
            let (dark, bright): (Vec<f64>, Vec<f64>) = positive.iter().partition(|&&v| v <= t);
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
            !dark.is_empty() && !bright.is_empty() && mean(&dark) < BACKGROUND_RATIO * mean(&bright)
        });
        let keep = Array3::from_shape_fn((nx, ny, nz), |(x, y, z)| {
            let v = s0[[x, y, z]];
            v.is_finite() && v > 0.0 && threshold.is_none_or(|t| v > t) && inputs.in_mask(x, y, z)
        });
        Self {
            keep,
            s0,
            threshold,
        }
    }

    /// Voxels kept.
    pub fn count(&self) -> usize {
        self.keep.iter().filter(|&&k| k).count()
    }
}

/// Otsu's threshold of `values`: the cut of their histogram that maximises the variance
/// between the two classes. `None` for fewer than two distinct values.
pub fn otsu_threshold(values: &[f64]) -> Option<f64> {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    // Also None when there are no values (lo infinite) or NaN got in.
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let width = (hi - lo) / BINS as f64;
    let mut histogram = [0usize; BINS];
    for &v in values {
        let bin = (((v - lo) / width) as usize).min(BINS - 1);
        histogram[bin] += 1;
    }
    let centre = |bin: usize| lo + (bin as f64 + 0.5) * width;
    let total = values.len() as f64;
    let sum: f64 = histogram
        .iter()
        .enumerate()
        .map(|(b, &n)| n as f64 * centre(b))
        .sum();
    let (mut weight, mut partial) = (0.0, 0.0);
    let mut best = (f64::NEG_INFINITY, None);
    for (bin, &n) in histogram.iter().enumerate().take(BINS - 1) {
        weight += n as f64;
        partial += n as f64 * centre(bin);
        if weight == 0.0 || weight == total {
            continue;
        }
        let (mean_dark, mean_bright) = (partial / weight, (sum - partial) / (total - weight));
        let between = weight * (total - weight) * (mean_dark - mean_bright).powi(2);
        if between > best.0 {
            best = (between, Some(lo + (bin as f64 + 1.0) * width));
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn otsu_separates_two_clusters() {
        let mut values: Vec<f64> = (0..300).map(|i| 10.0 + (i % 20) as f64).collect();
        values.extend((0..700).map(|i| 280.0 + (i % 50) as f64));
        let t = otsu_threshold(&values).unwrap();
        assert!(t > 29.0 && t < 280.0, "{t}");
        assert_eq!(otsu_threshold(&[5.0; 4]), None);
        assert_eq!(otsu_threshold(&[]), None);
    }
}
