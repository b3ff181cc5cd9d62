//! What the figure set shows, chosen from the data in one pass over the volume: per
//! voxel the mean amplitude of the ODF and its generalised fractional anisotropy (GFA),
//! the voxels the set looks at (the mask, or every voxel with a positive mean), the three
//! cuts of each plane and the regions of highest anisotropy that get zoomed panels.
//!
//! - Mean amplitude: c_00 Y_00 = c_00 / sqrt(4 pi), the ODF's mean over the sphere (the
//!   l = 0 term is the same in every basis).
//! - GFA (Tuch 2004), std / rms of the ODF over the sphere, from the coefficients:
//!   sqrt(1 - c_00^2 / sum c^2) with the coefficients of an orthonormal basis
//!   (`glyph::sh::orthonormal_factors`; Parseval).
//! - Cuts: the slices at the quartiles (1/4, 1/2, 3/4) of the amplitude inside the
//!   voxels looked at, summed over each slice of the plane, so the cuts follow the
//!   brain, not the field of view.
//! - Regions: cubes of `side` voxels whose mean GFA (voxels not looked at count 0) is
//!   highest, at least half of them looked at, none overlapping another; ties go to the
//!   lowest voxel index, so the choice is deterministic. Each zoomed panel shows the
//!   cube's slice with the most voxels looked at (the nearest the centre among equals).
use glam::DVec3;

use crate::volume::{Mask, SliceAxis, Volume};
use glyphcast::glyph::sh::orthonormal_factors;
use glyphcast::scene::GlyphKind;
use glyphcast::{Error, Result};

/// The three planes of the mosaic, in its row order.
pub const PLANES: [SliceAxis; 3] = [SliceAxis::Axial, SliceAxis::Coronal, SliceAxis::Sagittal];

/// Cuts per plane.
pub const CUTS: usize = 3;

/// Zoomed regions.
pub const REGIONS: usize = 3;

/// Per voxel maps and the voxels the set looks at.
pub struct Survey {
    /// The volume's voxel counts along x, y and z.
    pub dims: [usize; 3],
    /// Mean amplitude, x fastest (`index`); 0 where not looked at.
    pub amplitude: Vec<f64>,
    /// GFA in 0..=1; 0 where not looked at.
    pub gfa: Vec<f64>,
    /// Whether the set looks at the voxel.
    pub inside: Vec<bool>,
    /// Voxels looked at.
    pub count: usize,
}

/// One plane's cuts: the voxel axis it cuts and the indices along it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlaneCuts {
    /// The world plane (axial, coronal, sagittal).
    pub plane: SliceAxis,
    /// The plane as the volume's voxel axis closest to it.
    pub voxel_plane: SliceAxis,
    /// Indices along that voxel axis, increasing.
    pub indices: Vec<usize>,
}

/// A zoomed region: a cube of voxels.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// First voxel of the cube along i, j, k.
    pub start: [usize; 3],
    /// Voxels along i, j, k.
    pub size: [usize; 3],
    /// Mean GFA over the cube (voxels not looked at count 0).
    pub mean_gfa: f64,
    /// Mean amplitude over the voxels looked at in the cube.
    pub mean_amplitude: f64,
    /// Per voxel axis, the slice of the cube its zoomed panel shows: the one with the
    /// most voxels looked at, the nearest the centre among equals (a slice through the
    /// centre may miss a mask with holes).
    pub slices: [usize; 3],
}

impl Region {
    /// The voxel at the cube's centre (the lower middle for an even side).
    pub fn centre(&self) -> [usize; 3] {
        [0, 1, 2].map(|a| self.start[a] + (self.size[a] - 1) / 2)
    }

    /// The cube as voxel ranges, `i0:i1,j0:j1,k0:k1` (end exclusive).
    pub fn ranges_text(&self) -> String {
        let parts: Vec<String> = (0..3)
            .map(|a| format!("{}:{}", self.start[a], self.start[a] + self.size[a]))
            .collect();
        parts.join(",")
    }
}

impl Survey {
    /// Surveys an SH `volume`; `mask`, if given, limits the voxels looked at (and must
    /// have the volume's shape). An error names the file when no voxel is left.
    pub fn of(volume: &Volume, mask: Option<&Mask>) -> Result<Survey> {
        let GlyphKind::Sh {
            band,
            basis,
            legacy,
        } = volume.kind
        else {
            return Err(Error::input(
                &volume.file,
                "coefficients",
                "qc draws fibre ODFs: an SH volume is needed",
            ));
        };
        if let Some(mask) = mask
            && mask.dims != volume.dims
        {
            return Err(Error::input(
                &mask.file,
                "dim",
                format!(
                    "the mask is {:?} but the volume {} is {:?}",
                    mask.dims, volume.file, volume.dims
                ),
            ));
        }
        let factors = orthonormal_factors(band, basis, legacy);
        let dims = volume.dims;
        let voxels = dims.iter().product();
        let mut survey = Survey {
            dims,
            amplitude: vec![0.0; voxels],
            gfa: vec![0.0; voxels],
            inside: vec![false; voxels],
            count: 0,
        };
        let mean_factor = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let voxel = [i, j, k];
                    if mask.is_some_and(|m| !m.keeps(voxel)) {
                        continue;
                    }
                    let coeffs = volume.coefficients_view(voxel);
                    if coeffs.iter().any(|c| !c.is_finite()) || coeffs[0] <= 0.0 {
                        continue;
                    }
                    let power: f64 = coeffs
                        .iter()
                        .zip(&factors)
                        .map(|(c, f)| (c * f) * (c * f))
                        .sum();
                    let n = survey.index(voxel);
                    survey.amplitude[n] = coeffs[0] * mean_factor;
                    survey.gfa[n] = (1.0 - coeffs[0] * coeffs[0] / power).max(0.0).sqrt();
                    survey.inside[n] = true;
                    survey.count += 1;
                }
            }
        }
        if survey.count == 0 {
            let file = mask.map_or(volume.file.as_str(), |m| m.file.as_str());
            return Err(Error::input(
                file,
                "voxels",
                format!(
                    "no voxel of {} with finite coefficients and a positive mean amplitude{}",
                    volume.file,
                    if mask.is_some() {
                        " inside the mask"
                    } else {
                        ""
                    }
                ),
            ));
        }
        Ok(survey)
    }

    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The [`CUTS`] cuts of each of [`PLANES`] in `volume` (see the module notes).
    pub fn cuts(&self, volume: &Volume) -> Vec<PlaneCuts> {
        PLANES
            .iter()
            .map(|&plane| {
                let voxel_plane = plane.world_plane_in_voxels(volume.voxel_to_world.linear());
                let axis = voxel_plane.voxel_axis();
                let mut weight = vec![0.0; self.dims[axis]];
                for k in 0..self.dims[2] {
                    for j in 0..self.dims[1] {
                        for i in 0..self.dims[0] {
                            let voxel = [i, j, k];
                            weight[voxel[axis]] += self.amplitude[self.index(voxel)];
                        }
                    }
                }
                PlaneCuts {
                    plane,
                    voxel_plane,
                    indices: quartile_slices(&weight),
                }
            })
            .collect()
    }

    /// Up to [`REGIONS`] non-overlapping cubes of `side` voxels (fewer along an axis
    /// that is shorter) of highest mean GFA (see the module notes).
    pub fn regions(&self, side: usize) -> Vec<Region> {
        let size = self.dims.map(|n| side.clamp(1, n.max(1)));
        let gfa = PrefixSums::new(self.dims, |n| self.gfa[n]);
        let looked = PrefixSums::new(self.dims, |n| f64::from(u8::from(self.inside[n])));
        let amplitude = PrefixSums::new(self.dims, |n| self.amplitude[n]);
        let volume = (size[0] * size[1] * size[2]) as f64;
        let mut windows: Vec<(f64, [usize; 3])> = Vec::new();
        for k in 0..=self.dims[2] - size[2] {
            for j in 0..=self.dims[1] - size[1] {
                for i in 0..=self.dims[0] - size[0] {
                    let start = [i, j, k];
                    if 2.0 * looked.sum(start, size) < volume {
                        continue;
                    }
                    windows.push((gfa.sum(start, size) / volume, start));
                }
            }
        }
        // Highest first; equal scores in voxel order (the sort is stable).
        windows.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut chosen: Vec<Region> = Vec::new();
        for (score, start) in windows {
            if chosen.len() == REGIONS {
                break;
            }
            let overlaps = chosen.iter().any(|r| {
                (0..3).all(|a| start[a] < r.start[a] + r.size[a] && r.start[a] < start[a] + size[a])
            });
            if overlaps {
                continue;
            }
            let inside = looked.sum(start, size).max(1.0);
            let slices = [0, 1, 2].map(|axis| {
                let centre = start[axis] + (size[axis] - 1) / 2;
                (start[axis]..start[axis] + size[axis])
                    .map(|index| {
                        let mut from = start;
                        let mut extent = size;
                        (from[axis], extent[axis]) = (index, 1);
                        (looked.sum(from, extent), index)
                    })
                    .max_by(|a, b| {
                        a.0.total_cmp(&b.0)
                            .then(b.1.abs_diff(centre).cmp(&a.1.abs_diff(centre)))
                            .then(b.1.cmp(&a.1))
                    })
                    .map_or(centre, |(_, index)| index)
            });
            chosen.push(Region {
                start,
                size,
                mean_gfa: score,
                mean_amplitude: amplitude.sum(start, size) / inside,
                slices,
            });
        }
        chosen
    }
}

/// The side of the zoomed cubes for a volume of `dims`: a quarter of the shortest side,
/// 4 to 8 voxels (a few glyphs across, big enough to see their lobes).
pub fn region_side(dims: [usize; 3]) -> usize {
    let shortest = dims.into_iter().min().unwrap_or(1);
    (shortest / 4).clamp(4, 8)
}

/// The slices at the quartiles of `weight`'s cumulative sum, distinct where the axis
/// has slices enough that carry weight: the first slice whose running sum reaches q of
/// the total, for q = 1/4, 1/2, 3/4; a slice taken twice moves to the nearest
/// unused slice with weight.
pub fn quartile_slices(weight: &[f64]) -> Vec<usize> {
    let total: f64 = weight.iter().sum();
    let carrying: Vec<usize> = (0..weight.len()).filter(|&s| weight[s] > 0.0).collect();
    let mut picked: Vec<usize> = Vec::with_capacity(CUTS);
    for q in 1..=CUTS {
        let target = total * q as f64 / (CUTS + 1) as f64;
        let mut running = 0.0;
        let mut slice = carrying.last().copied().unwrap_or(0);
        for &s in &carrying {
            running += weight[s];
            if running >= target {
                slice = s;
                break;
            }
        }
        if picked.contains(&slice) {
            let free = carrying
                .iter()
                .copied()
                .filter(|s| !picked.contains(s))
                .min_by_key(|&s| (s.abs_diff(slice), s));
            if let Some(free) = free {
                slice = free;
            }
        }
        picked.push(slice);
    }
    picked.sort_unstable();
    picked
}

/// Sums over boxes of a 3D map in constant time (a summed-volume table).
struct PrefixSums {
    dims: [usize; 3],
    table: Vec<f64>,
}

impl PrefixSums {
    fn new(dims: [usize; 3], value: impl Fn(usize) -> f64) -> PrefixSums {
        let [nx, ny, nz] = dims.map(|n| n + 1);
        let mut table = vec![0.0; nx * ny * nz];
        let at = |i: usize, j: usize, k: usize| i + nx * (j + ny * k);
        for k in 1..nz {
            for j in 1..ny {
                for i in 1..nx {
                    let v = value((i - 1) + dims[0] * ((j - 1) + dims[1] * (k - 1)));
                    table[at(i, j, k)] = v
                        + table[at(i - 1, j, k)]
                        + table[at(i, j - 1, k)]
                        + table[at(i, j, k - 1)]
                        - table[at(i - 1, j - 1, k)]
                        - table[at(i - 1, j, k - 1)]
                        - table[at(i, j - 1, k - 1)]
                        + table[at(i - 1, j - 1, k - 1)];
                }
            }
        }
        PrefixSums { dims, table }
    }

    /// The sum over the box from `start` of `size` voxels.
    fn sum(&self, start: [usize; 3], size: [usize; 3]) -> f64 {
        let [nx, ny, _] = self.dims.map(|n| n + 1);
        let at = |i: usize, j: usize, k: usize| self.table[i + nx * (j + ny * k)];
        let [i0, j0, k0] = start;
        let [i1, j1, k1] = [0, 1, 2].map(|a| start[a] + size[a]);
        at(i1, j1, k1) - at(i0, j1, k1) - at(i1, j0, k1) - at(i1, j1, k0)
            + at(i0, j0, k1)
            + at(i0, j1, k0)
            + at(i1, j0, k0)
            - at(i0, j0, k0)
    }
}

/// The world position of voxel `voxel`'s centre.
pub fn voxel_world(volume: &Volume, voxel: [usize; 3]) -> DVec3 {
    volume
        .voxel_to_world
        .voxel_center(DVec3::from_array(voxel.map(|v| v as f64)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::nifti::{AffineSource, VoxelToWorld};
    use crate::volume::VolumeKind;
    use glyphcast::scene::ShBasis;

    /// GFA and amplitude from the coefficients: an isotropic ODF has GFA 0, a band-2
    /// one sqrt(1 - c00^2 / (c00^2 + c20^2)) in every basis (its zonal term is the same
    /// in all), legacy tournier07's m != 0 terms count half; the mask and non-finite or
    /// non-positive voxels are left out.
    #[test]
    fn amplitude_and_gfa_come_from_the_coefficients() {
        let mut data = ndarray::Array4::<f64>::zeros((4, 1, 1, 6));
        data[[0, 0, 0, 0]] = 2.0; // isotropic
        data[[1, 0, 0, 0]] = 1.0;
        data[[1, 0, 0, 3]] = 1.0; // (l, m) = (2, 0)
        data[[2, 0, 0, 0]] = 1.0;
        data[[2, 0, 0, 1]] = 1.0; // (2, -2)
        data[[3, 0, 0, 0]] = f64::NAN;
        let map = VoxelToWorld::new(glam::DMat4::IDENTITY, AffineSource::Sform, "v", "affine")
            .expect("identity");
        for legacy in [false, true] {
            let kind = VolumeKind::Sh {
                basis: ShBasis::Tournier07,
                legacy,
            };
            let volume = Volume::new("v", data.clone(), kind, map).expect("a volume");
            let survey = Survey::of(&volume, None).expect("surveyed");
            assert_eq!(survey.count, 3);
            assert!(!survey.inside[3]);
            assert!(
                (survey.amplitude[0] - 2.0 / (4.0 * std::f64::consts::PI).sqrt()).abs() < 1e-15
            );
            assert_eq!(survey.gfa[0], 0.0);
            assert!((survey.gfa[1] - 0.5f64.sqrt()).abs() < 1e-15);
            let expected = if legacy {
                (1.0f64 / 3.0).sqrt()
            } else {
                0.5f64.sqrt()
            };
            assert!((survey.gfa[2] - expected).abs() < 1e-15, "{legacy}");
            let mask = Mask::new(
                "m",
                &ndarray::Array3::from_shape_vec((4, 1, 1), vec![0.0, 1.0, 0.0, 1.0])
                    .expect("a mask"),
            );
            let masked = Survey::of(&volume, Some(&mask)).expect("masked");
            assert_eq!(masked.count, 1);
            assert!(masked.inside[1]);
        }
        let empty = ndarray::Array4::<f64>::zeros((2, 1, 1, 6));
        let kind = VolumeKind::Sh {
            basis: ShBasis::Tournier07,
            legacy: false,
        };
        let volume = Volume::new("zeros.nii", empty, kind, map).expect("a volume");
        let err = Survey::of(&volume, None).err().expect("nothing to look at");
        assert!(err.to_string().contains("zeros.nii"), "{err}");
    }

    #[test]
    fn quartiles_follow_the_weight_and_stay_distinct() {
        // Weight only in slices 4..=7: the cuts stay there, not at the field of view's
        // quarters.
        let weight = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0];
        assert_eq!(quartile_slices(&weight), [4, 5, 6]);
        // One heavy slice: the others move to the nearest slices with weight.
        let weight = [0.0, 1.0, 100.0, 1.0, 0.0];
        assert_eq!(quartile_slices(&weight), [1, 2, 3]);
        // Too few slices with weight: repeated rather than empty.
        assert_eq!(quartile_slices(&[0.0, 2.0, 0.0]), [1, 1, 1]);
    }

    #[test]
    fn prefix_sums_sum_boxes() {
        let dims = [4, 3, 5];
        let value = |n: usize| (n * 7 % 11) as f64;
        let sums = PrefixSums::new(dims, value);
        let (start, size) = ([1, 0, 2], [2, 3, 2]);
        let mut expected = 0.0;
        for k in 2..4 {
            for j in 0..3 {
                for i in 1..3 {
                    expected += value(i + 4 * (j + 3 * k));
                }
            }
        }
        assert_eq!(sums.sum(start, size), expected);
    }

    #[test]
    fn regions_are_the_most_anisotropic_cubes_and_do_not_overlap() {
        let dims = [12, 12, 12];
        let n = 12 * 12 * 12;
        let mut survey = Survey {
            dims,
            amplitude: vec![1.0; n],
            gfa: vec![0.1; n],
            inside: vec![true; n],
            count: n,
        };
        // Two anisotropic blocks: the stronger one is chosen first.
        for (corner, g) in [([6, 6, 6], 0.9), ([0, 0, 0], 0.7)] {
            for k in 0..4 {
                for j in 0..4 {
                    for i in 0..4 {
                        let v = [corner[0] + i, corner[1] + j, corner[2] + k];
                        let at = survey.index(v);
                        survey.gfa[at] = g;
                    }
                }
            }
        }
        let regions = survey.regions(4);
        assert_eq!(regions.len(), 3);
        assert_eq!(regions[0].start, [6, 6, 6]);
        assert!((regions[0].mean_gfa - 0.9).abs() < 1e-12);
        assert_eq!(regions[1].start, [0, 0, 0]);
        assert_eq!(regions[0].ranges_text(), "6:10,6:10,6:10");
        assert_eq!(regions[0].centre(), [7, 7, 7]);
        assert_eq!(
            regions[0].slices,
            [7, 7, 7],
            "every slice full: the centre's"
        );
        // A hole through the centre's slice: the panel moves to the nearest full slice.
        for j in 0..12 {
            for i in 0..12 {
                let at = survey.index([i, j, 7]);
                survey.inside[at] = false;
            }
        }
        let moved = survey.regions(4);
        assert_eq!(moved[0].start, [6, 6, 6]);
        assert_eq!(moved[0].slices, [7, 7, 6]);
        for (a, r) in regions.iter().enumerate() {
            for s in &regions[a + 1..] {
                assert!(
                    (0..3).any(|x| r.start[x] + 4 <= s.start[x] || s.start[x] + 4 <= r.start[x])
                );
            }
        }
    }
}
