//! Maxima of an ODF's SH series: `glyphcast peaks`.
//!
//! The series is evaluated on a geodesic sphere of 2562 directions (at most 4.6 degrees
//! apart); every vertex of one hemisphere at least as high as its neighbours is a
//! candidate, and those that can reach the relative threshold are refined by hill
//! climbing on the sphere with a step that halves down to 1e-6 radians. Candidates
//! are taken from the highest down; one within the minimum separation angle of a peak
//! already taken (antipodes count as the same direction), or below the relative
//! threshold times the highest, or not positive, is dropped.
//!
//! Output layout (MRtrix `sh2peaks`): 3 N values per voxel, peak k's direction scaled by
//! its amplitude at 3k, 3k+1, 3k+2, highest first, NaN where fewer peaks were found. Each
//! direction is given with z >= 0, in the frame of the ODF's coefficients.
use glam::DVec3;
use nalgebra::DMatrix;
use ndarray::Array4;

use super::sphere::GeodesicSphere;
use crate::setting::DmriSetting;
use glyphcast::glyph::sh::{check_band, sh_basis_values, sh_count, sh_eval};
use glyphcast::scene::ShBasis;
use glyphcast::{Error, Result};

/// Default number of peaks per voxel.
pub const DEFAULT_PEAK_COUNT: usize = 3;
/// Default relative threshold (DIPY's `relative_peak_threshold`).
pub const DEFAULT_RELATIVE_THRESHOLD: f64 = 0.5;
/// Default minimum angle between two peaks, degrees (DIPY's `min_separation_angle`).
pub const DEFAULT_MIN_SEPARATION: f64 = 25.0;

/// Frequency of the search sphere: 10 * 16^2 + 2 = 2562 directions.
const SEARCH_FREQUENCY: usize = 16;
/// A bound on the angle between neighbouring vertices of the search sphere (radians;
/// measured 4.6 degrees, `sphere` tests).
const SEARCH_SPACING: f64 = 5.0 * std::f64::consts::PI / 180.0;
/// Fraction of the largest vertex value by which a candidate below the relative
/// threshold is still refined.
const REFINE_MARGIN: f64 = 0.1;
/// The refinement stops when its step falls below this angle (radians).
const REFINE_TOLERANCE: f64 = 1e-6;

/// How peaks are chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakOptions {
    /// At most this many peaks per voxel.
    pub count: usize,
    /// Peaks below this fraction of the voxel's highest are dropped (0 to 1).
    pub relative_threshold: f64,
    /// Peaks closer than this angle (degrees) to a higher one are dropped.
    pub min_separation_degrees: f64,
}

impl Default for PeakOptions {
    fn default() -> Self {
        Self {
            count: DEFAULT_PEAK_COUNT,
            relative_threshold: DEFAULT_RELATIVE_THRESHOLD,
            min_separation_degrees: DEFAULT_MIN_SEPARATION,
        }
    }
}

impl PeakOptions {
    /// Checks the options; errors name the [`Setting`](glyphcast::Setting).
    pub fn validate(&self) -> Result<()> {
        if !(1..=16).contains(&self.count) {
            return Err(Error::setting_value(
                DmriSetting::Count,
                self.count,
                "the number of peaks must be from 1 to 16",
            ));
        }
        if !(0.0..=1.0).contains(&self.relative_threshold) {
            return Err(Error::setting_value(
                DmriSetting::RelativeThreshold,
                self.relative_threshold,
                "must be in 0 to 1",
            ));
        }
        if !(0.0..=90.0).contains(&self.min_separation_degrees) {
            return Err(Error::setting_value(
                DmriSetting::MinSeparation,
                self.min_separation_degrees,
                "must be in 0 to 90 degrees",
            ));
        }
        Ok(())
    }
}

/// One maximum: a unit direction (z >= 0) and the ODF's value there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// Unit direction.
    pub direction: DVec3,
    /// The ODF at `direction`.
    pub value: f64,
}

/// The search sphere and basis for series of one band and basis.
#[derive(Clone, Debug)]
pub struct PeakFinder {
    band: u32,
    basis: ShBasis,
    legacy: bool,
    sphere: GeodesicSphere,
    /// Basis values at the sphere's vertices, one row per vertex.
    values: DMatrix<f64>,
    options: PeakOptions,
}

impl PeakFinder {
    /// A finder for series up to `band` in `basis`. Err for an invalid band or options.
    pub fn new(band: u32, basis: ShBasis, legacy: bool, options: PeakOptions) -> Result<Self> {
        check_band(band)?;
        options.validate()?;
        let sphere = GeodesicSphere::new(SEARCH_FREQUENCY);
        let rows: Vec<f64> = sphere
            .vertices
            .iter()
            .flat_map(|u| sh_basis_values(band, basis, legacy, *u))
            .collect();
        let values = DMatrix::from_row_slice(sphere.vertices.len(), sh_count(band), &rows);
        Ok(Self {
            band,
            basis,
            legacy,
            sphere,
            values,
            options,
        })
    }

    fn eval(&self, coeffs: &[f64], u: DVec3) -> f64 {
        sh_eval(self.band, self.basis, self.legacy, coeffs, u)
    }

    /// The peaks of the series `coeffs`, highest first: none for an all-zero series, and
    /// none for an isotropic one (band 0 alone, as a grey-matter or CSF tissue ODF), which
    /// has the same value in every direction and so no maximum.
    pub fn find(&self, coeffs: &[f64]) -> Vec<Peak> {
        if is_isotropic(coeffs) || coeffs.iter().any(|c| !c.is_finite()) {
            return Vec::new();
        }
        let on_sphere: Vec<f64> = self
            .values
            .row_iter()
            .map(|row| row.iter().zip(coeffs).map(|(a, b)| a * b).sum())
            .collect();
        // Maxima come in antipodal pairs: one hemisphere's vertices are enough.
        let maxima: Vec<usize> = (0..on_sphere.len())
            .filter(|&i| {
                let (u, v) = (self.sphere.vertices[i], on_sphere[i]);
                (u.z, u.y, u.x) > (0.0, 0.0, 0.0)
                    && v > 0.0
                    && self.sphere.neighbours[i]
                        .iter()
                        .all(|&j| v > on_sphere[j] || (v == on_sphere[j] && i < j))
            })
            .collect();
        let Some(top) = maxima.iter().map(|&i| on_sphere[i]).reduce(f64::max) else {
            return Vec::new();
        };
        // Refining raises a vertex's value by far less than REFINE_MARGIN of the largest
        // (the vertices are 4.6 degrees apart at most), so maxima below this cannot
        // reach the relative threshold and are not refined.
        let floor = (self.options.relative_threshold - REFINE_MARGIN) * top;
        let mut candidates: Vec<Peak> = maxima
            .into_iter()
            .filter(|&i| on_sphere[i] >= floor)
            .map(|i| self.refine(coeffs, self.sphere.vertices[i], on_sphere[i]))
            .collect();
        candidates.sort_by(|a, b| b.value.total_cmp(&a.value));
        let Some(highest) = candidates.first().map(|p| p.value) else {
            return Vec::new();
        };
        let min_cos = self.options.min_separation_degrees.to_radians().cos();
        let mut peaks: Vec<Peak> = Vec::new();
        for c in candidates {
            if peaks.len() == self.options.count
                || c.value < self.options.relative_threshold * highest
            {
                break;
            }
            if peaks
                .iter()
                .all(|p| p.direction.dot(c.direction).abs() < min_cos)
            {
                let direction = if c.direction.z < 0.0 {
                    -c.direction
                } else {
                    c.direction
                };
                peaks.push(Peak {
                    direction,
                    value: c.value,
                });
            }
        }
        peaks
    }

    /// Hill climbing from `start`: tries a step either way along two tangent directions,
    /// moves to the best improvement, and halves the step when none improves.
    fn refine(&self, coeffs: &[f64], start: DVec3, value: f64) -> Peak {
        let (mut u, mut best) = (start, value);
        let mut step = SEARCH_SPACING / 2.0;
        while step > REFINE_TOLERANCE {
            let e1 = u.any_orthonormal_vector();
            let e2 = u.cross(e1);
            let moves = [e1, -e1, e2, -e2];
            let better = moves
                .iter()
                .map(|m| (u + *m * step).normalize())
                .map(|v| (v, self.eval(coeffs, v)))
                .filter(|(_, f)| *f > best)
                .max_by(|a, b| a.1.total_cmp(&b.1));
            match better {
                Some((v, f)) => (u, best) = (v, f),
                None => step /= 2.0,
            }
        }
        Peak {
            direction: u,
            value: best,
        }
    }
}

/// Whether the SH series `coeffs` is constant on the sphere: every coefficient past
/// band 0 is zero (also for the empty and the all-zero series).
pub fn is_isotropic(coeffs: &[f64]) -> bool {
    coeffs.iter().skip(1).all(|&c| c == 0.0)
}

/// The peaks of every voxel of `coeffs` ([x, y, z, coefficient]) in MRtrix's layout
/// ([x, y, z, 3 count], NaN where missing), on every core.
pub fn peak_volume(coeffs: &Array4<f64>, finder: &PeakFinder) -> Result<Array4<f64>> {
    let (nx, ny, nz, k) = coeffs.dim();
    if k != sh_count(finder.band) {
        return Err(Error::data(
            "SH coefficients per voxel",
            glyphcast::error::Problem::Count {
                expected: sh_count(finder.band),
                found: k,
            },
        ));
    }
    let count = finder.options.count;
    let voxels: Vec<[usize; 3]> = (0..nz)
        .flat_map(|z| (0..ny).flat_map(move |y| (0..nx).map(move |x| [x, y, z])))
        .collect();
    let found = glyphcast::parallel::map_chunks(&voxels, "finding peaks", |&[x, y, z]| {
        let series: Vec<f64> = coeffs.slice(ndarray::s![x, y, z, ..]).to_vec();
        Ok(finder.find(&series))
    })?;
    let mut out = Array4::from_elem((nx, ny, nz, 3 * count), f64::NAN);
    for ([x, y, z], peaks) in voxels.iter().zip(found) {
        let mut lane = out.slice_mut(ndarray::s![*x, *y, *z, ..]);
        for (i, p) in peaks.iter().enumerate() {
            let v = p.direction * p.value;
            lane[3 * i] = v.x;
            lane[3 * i + 1] = v.y;
            lane[3 * i + 2] = v.z;
        }
    }
    Ok(out)
}

/// `peaks` (the layout of [`peak_volume`]) with every peak vector turned by `rotation`
/// (from the ODF's frame into the frame the output file is read in), again with z >= 0;
/// NaN (absent) peaks stay NaN.
pub fn rotate_peaks(peaks: &mut Array4<f64>, rotation: glam::DMat3) {
    for mut lane in peaks.lanes_mut(ndarray::Axis(3)) {
        for k in 0..lane.len() / 3 {
            let v = DVec3::new(lane[3 * k], lane[3 * k + 1], lane[3 * k + 2]);
            if !v.is_finite() {
                continue;
            }
            let turned = rotation * v;
            let turned = if turned.z < 0.0 { -turned } else { turned };
            lane[3 * k] = turned.x;
            lane[3 * k + 1] = turned.y;
            lane[3 * k + 2] = turned.z;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glyphcast::glyph::sh::ShFitter;

    #[test]
    fn rotated_peaks_keep_nan_lengths_and_z_up() {
        let mut peaks = Array4::from_elem((1, 1, 1, 6), f64::NAN);
        for (c, v) in [0.0, 0.6, 0.8].into_iter().enumerate() {
            peaks[[0, 0, 0, c]] = 2.0 * v;
        }
        let first = |peaks: &Array4<f64>| DVec3::from_array([0, 1, 2].map(|c| peaks[[0, 0, 0, c]]));
        // A half turn about x: (0, 1.2, 1.6) -> (0, -1.2, -1.6) -> flipped to z >= 0.
        rotate_peaks(
            &mut peaks,
            glam::DMat3::from_rotation_x(std::f64::consts::PI),
        );
        let v = first(&peaks);
        assert!((v - DVec3::new(0.0, 1.2, 1.6)).length() < 1e-12, "{v}");
        assert!((3..6).all(|c| peaks[[0, 0, 0, c]].is_nan()));
        // A quarter turn about y: (0, 1.2, 1.6) -> (1.6, 1.2, 0).
        rotate_peaks(
            &mut peaks,
            glam::DMat3::from_rotation_y(std::f64::consts::FRAC_PI_2),
        );
        let v = first(&peaks);
        assert!((v - DVec3::new(1.6, 1.2, 0.0)).length() < 1e-12, "{v}");
    }

    /// An fODF of sharp lobes (u . d)^20 with weights, fitted to band 8.
    fn lobes(fibres: &[(DVec3, f64)], basis: (ShBasis, bool)) -> Vec<f64> {
        let sphere = GeodesicSphere::new(10);
        let fitter = ShFitter::new(8, basis.0, basis.1, &sphere.vertices, 0.0).unwrap();
        let samples: Vec<f64> = sphere
            .vertices
            .iter()
            .map(|u| {
                fibres
                    .iter()
                    .map(|(d, w)| w * u.dot(d.normalize()).powi(20))
                    .sum()
            })
            .collect();
        fitter.fit(&samples)
    }

    fn angle(a: DVec3, b: DVec3) -> f64 {
        a.dot(b).abs().clamp(0.0, 1.0).acos().to_degrees()
    }

    #[test]
    fn finds_known_fibre_directions() {
        let one = DVec3::new(0.3, -0.8, 0.52).normalize();
        let two = DVec3::new(0.9, 0.1, -0.3).normalize();
        let three = one.cross(two).normalize();
        let basis = (ShBasis::Tournier07, false);
        let finder = PeakFinder::new(8, basis.0, basis.1, PeakOptions::default()).unwrap();
        // Crossing at an angle other than 90 degrees moves band-8 maxima a little
        // towards each other; orthogonal fibres keep theirs.
        let c = lobes(&[(one, 1.0), (three, 0.8)], basis);
        let peaks = finder.find(&c);
        assert_eq!(peaks.len(), 2, "{peaks:?}");
        assert!(angle(peaks[0].direction, one) < 0.5, "{peaks:?}");
        assert!(angle(peaks[1].direction, three) < 0.5, "{peaks:?}");
        assert!(peaks.iter().all(|p| p.direction.z >= 0.0));
        assert!(peaks[0].value > peaks[1].value);
        let value = sh_eval(8, basis.0, basis.1, &c, peaks[0].direction);
        assert!((value - peaks[0].value).abs() < 1e-12);
        // A single fibre: one peak, the maximum over a fine sweep.
        let c = lobes(&[(two, 1.0)], basis);
        let peaks = finder.find(&c);
        assert_eq!(peaks.len(), 1, "{peaks:?}");
        assert!(angle(peaks[0].direction, two) < 0.1);
        // A weak third fibre is cut by the relative threshold, kept without it.
        let c = lobes(&[(one, 1.0), (three, 0.9), (one.cross(three), 0.3)], basis);
        assert_eq!(finder.find(&c).len(), 2);
        let all = PeakOptions {
            relative_threshold: 0.1,
            ..PeakOptions::default()
        };
        let finder = PeakFinder::new(8, basis.0, basis.1, all).unwrap();
        let peaks = finder.find(&c);
        assert_eq!(peaks.len(), 3, "{peaks:?}");
        assert!(angle(peaks[2].direction, one.cross(three)) < 0.5);
        assert!(finder.find(&vec![0.0; 45]).is_empty());
    }
}
