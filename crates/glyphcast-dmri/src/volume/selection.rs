//! Which voxels become glyphs: one slice, optionally cut down by voxel index ranges,
//! then by a mask.
//!
//! A [`Slice`] names a voxel axis, as DIPY and FURY do: sagittal is a slice of constant
//! i, coronal of constant j, axial of constant k. The command line means the world's
//! planes instead (mrview's way): [`SliceAxis::world_plane_in_voxels`] finds the voxel
//! axis closest to the world axis a plane name stands for, which for the usual axial
//! acquisitions is the same axis. The camera looks at the slice face on (see `framing`).
use glam::DMat3;
use std::fmt;
use std::ops::Range;
use std::str::FromStr;

use super::input::show_shape;
use glyphcast::error::quoted;
use glyphcast::{Error, Result, Setting};

/// The voxel axis a slice is perpendicular to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SliceAxis {
    /// Constant i.
    Sagittal,
    /// Constant j.
    Coronal,
    /// Constant k.
    Axial,
}

/// A slice of the volume; `index` None is the middle slice (n / 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slice {
    /// The voxel axis the slice is perpendicular to.
    pub axis: SliceAxis,
    /// The voxel index along that axis, from 0.
    pub index: Option<usize>,
}

/// Three orthogonal slices at once: the voxel indices of the sagittal (constant i),
/// coronal (constant j) and axial (constant k) slice; None is the middle (n / 2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Slices {
    /// The i, j and k of the sagittal, coronal and axial slice.
    pub indices: [Option<usize>; 3],
}

/// Half-open index ranges per voxel axis; None is the whole axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VoxelRanges {
    /// Per axis i, j, k: None for the whole axis, else (start, end) with end exclusive and
    /// a missing end meaning the axis's own (`--voxels 4:,:,:9`).
    pub axes: [Option<(Option<usize>, Option<usize>)>; 3],
}

/// The voxels of a slice within the ranges: a box of voxel indices, one voxel thick
/// along the slice axis.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SliceRegion {
    /// The voxel axis the slice is perpendicular to.
    pub slice: SliceAxis,
    /// The slice's voxel index along that axis.
    pub index: usize,
    /// Index ranges along i, j, k.
    pub ranges: [Range<usize>; 3],
}

impl SliceAxis {
    /// The voxel axis (0 = i, 1 = j, 2 = k) the slice is perpendicular to.
    pub fn voxel_axis(self) -> usize {
        match self {
            SliceAxis::Sagittal => 0,
            SliceAxis::Coronal => 1,
            SliceAxis::Axial => 2,
        }
    }

    /// The slice perpendicular to voxel axis `axis` (0 = i, 1 = j, anything else k).
    pub fn of_voxel_axis(axis: usize) -> SliceAxis {
        match axis {
            0 => SliceAxis::Sagittal,
            1 => SliceAxis::Coronal,
            _ => SliceAxis::Axial,
        }
    }

    /// The slice of the voxel axis closest to the world plane `self` names (sagittal
    /// across world x, coronal across y, axial across z) in a volume whose affine has the
    /// linear part `linear`. Voxel axes are matched to world axes by the permutation that
    /// aligns them best (the largest sum of |cosines|), so the three planes stay three
    /// different voxel axes even on an oblique grid.
    pub fn world_plane_in_voxels(self, linear: DMat3) -> SliceAxis {
        const PERMUTATIONS: [[usize; 3]; 6] = [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ];
        // world_of[c]: the world axis voxel axis c is matched to.
        let alignment = |world_of: &[usize; 3]| -> f64 {
            (0..3)
                .map(|c| {
                    let column = linear.col(c);
                    column[world_of[c]].abs() / column.length()
                })
                .sum()
        };
        let best = PERMUTATIONS
            .iter()
            .max_by(|a, b| alignment(a).total_cmp(&alignment(b)))
            .unwrap_or(&PERMUTATIONS[0]);
        let world = self.voxel_axis();
        let voxel = best.iter().position(|&w| w == world).unwrap_or(world);
        SliceAxis::of_voxel_axis(voxel)
    }

    /// The plane's name: sagittal, coronal or axial.
    pub fn name(self) -> &'static str {
        match self {
            SliceAxis::Sagittal => "sagittal",
            SliceAxis::Coronal => "coronal",
            SliceAxis::Axial => "axial",
        }
    }
}

impl Default for Slice {
    /// The middle axial slice.
    fn default() -> Self {
        Slice {
            axis: SliceAxis::Axial,
            index: None,
        }
    }
}

impl fmt::Display for Slice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.index {
            Some(index) => write!(f, "{}:{index}", self.axis.name()),
            None => write!(f, "{} (middle)", self.axis.name()),
        }
    }
}

impl FromStr for Slice {
    type Err = Error;

    /// `axial`, `coronal` or `sagittal`, optionally followed by `:INDEX` or `:mid`.
    fn from_str(text: &str) -> Result<Self> {
        let (name, index) = match text.split_once(':') {
            Some((name, index)) => (name, Some(index)),
            None => (text, None),
        };
        let axis = match name {
            "sagittal" => SliceAxis::Sagittal,
            "coronal" => SliceAxis::Coronal,
            "axial" => SliceAxis::Axial,
            _ => {
                return Err(Error::setting_value(
                    Setting::Slice,
                    format!("'{}'", quoted(text)),
                    "expected axial, coronal or sagittal, optionally :INDEX",
                ));
            }
        };
        // `:mid` says the default (the middle) explicitly.
        let index = index
            .filter(|&index| index != "mid")
            .map(|index| {
                index.parse::<usize>().map_err(|_| {
                    Error::setting_value(
                        Setting::Slice,
                        format!("'{}'", quoted(text)),
                        format!(
                            "index '{}' is not a voxel index (0, 1, 2, ...) or mid",
                            quoted(index)
                        ),
                    )
                })
            })
            .transpose()?;
        Ok(Slice { axis, index })
    }
}

impl Slices {
    /// The slice perpendicular to voxel axis `axis` (0 = i, 1 = j, 2 = k).
    pub fn slice(&self, axis: usize) -> Slice {
        Slice {
            axis: SliceAxis::of_voxel_axis(axis),
            index: self.indices[axis],
        }
    }
}

impl FromStr for Slices {
    type Err = Error;

    /// `mid` (the middle of each axis) or `I,J,K`, voxel indices.
    fn from_str(text: &str) -> Result<Self> {
        if text == "mid" {
            return Ok(Slices::default());
        }
        let invalid =
            |why: &str| Error::setting_value(Setting::Slices, format!("'{}'", quoted(text)), why);
        let parts: Vec<&str> = text.split(',').collect();
        if parts.len() != 3 {
            return Err(invalid("expected mid or three voxel indices I,J,K"));
        }
        let mut indices = [None; 3];
        for (index, part) in indices.iter_mut().zip(parts) {
            let part = part.trim();
            *index =
                Some(part.parse::<usize>().map_err(|_| {
                    invalid(&format!("'{part}' is not a voxel index (0, 1, 2, ...)"))
                })?);
        }
        Ok(Slices { indices })
    }
}

impl FromStr for VoxelRanges {
    type Err = Error;

    /// `i0:i1,j0:j1,k0:k1`, half-open; either end of a range may be left out (`:`, `4:`,
    /// `:9`).
    fn from_str(text: &str) -> Result<Self> {
        let invalid =
            |why: &str| Error::setting_value(Setting::Voxels, format!("'{}'", quoted(text)), why);
        let parts: Vec<&str> = text.split(',').collect();
        if parts.len() != 3 {
            return Err(invalid("expected three ranges i0:i1,j0:j1,k0:k1"));
        }
        let mut axes = [None; 3];
        for (axis, part) in axes.iter_mut().zip(parts) {
            let (lo, hi) = part
                .split_once(':')
                .ok_or_else(|| invalid(&format!("'{part}' is not a range START:END")))?;
            let bound = |s: &str| -> Result<Option<usize>> {
                let s = s.trim();
                if s.is_empty() {
                    return Ok(None);
                }
                s.parse::<usize>()
                    .map(Some)
                    .map_err(|_| invalid(&format!("'{s}' is not a voxel index")))
            };
            let (lo, hi) = (bound(lo)?, bound(hi)?);
            if let (Some(lo), Some(hi)) = (lo, hi)
                && lo >= hi
            {
                return Err(invalid(&format!(
                    "range {lo}:{hi} is empty (the end is exclusive)"
                )));
            }
            *axis = Some((lo, hi));
        }
        Ok(VoxelRanges { axes })
    }
}

impl VoxelRanges {
    /// `region` (index ranges along i, j, k) cut down to these ranges.
    fn cut(&self, mut region: [Range<usize>; 3]) -> [Range<usize>; 3] {
        for (range, wanted) in region.iter_mut().zip(self.axes) {
            if let Some((lo, hi)) = wanted {
                let lo = lo.unwrap_or(0).max(range.start);
                let hi = hi.unwrap_or(usize::MAX).min(range.end);
                *range = lo..hi.max(lo);
            }
        }
        region
    }

    /// The voxel box a block view draws: these ranges in a volume of `dims` voxels (the
    /// whole volume without any); `file` names the error when they leave no voxel.
    pub fn block(&self, dims: [usize; 3], file: &str) -> Result<[Range<usize>; 3]> {
        let block = self.cut([0..dims[0], 0..dims[1], 0..dims[2]]);
        if block.iter().any(|r| r.is_empty()) {
            return Err(Error::input(
                file,
                Setting::Voxels.name(),
                glyphcast::message![
                    "the ranges of ",
                    Setting::Voxels,
                    format!(" leave no voxel of this {} volume", show_shape(&dims))
                ],
            ));
        }
        Ok(block)
    }
}

/// The voxel box `block` as the voxel ranges' text, `i0:i1,j0:j1,k0:k1`.
pub fn show_block(block: &[Range<usize>; 3]) -> String {
    block
        .iter()
        .map(|r| format!("{}:{}", r.start, r.end))
        .collect::<Vec<_>>()
        .join(",")
}

impl SliceRegion {
    /// The voxels of `slice` within `ranges` in a volume of `dims` voxels; `file` names
    /// errors: an index outside the volume, or ranges that leave no voxel of the slice.
    pub fn new(dims: [usize; 3], slice: Slice, ranges: &VoxelRanges, file: &str) -> Result<Self> {
        let axis = slice.axis.voxel_axis();
        let length = dims[axis];
        let index = slice.index.unwrap_or(length / 2);
        if index >= length {
            return Err(Error::input(
                file,
                format!("dim[{}]", axis + 1),
                glyphcast::message![
                    Setting::Slice.with(slice),
                    format!(
                        ": index {index} is outside the volume's {} voxels along {} (0..={})",
                        length,
                        ["i", "j", "k"][axis],
                        length.saturating_sub(1)
                    )
                ],
            ));
        }
        let mut region: [Range<usize>; 3] = [0..dims[0], 0..dims[1], 0..dims[2]];
        region[axis] = index..index + 1;
        let region = ranges.cut(region);
        if region.iter().any(|r| r.is_empty()) {
            return Err(Error::input(
                file,
                Setting::Voxels.name(),
                glyphcast::message![
                    "the ranges of ",
                    Setting::Voxels,
                    format!(
                        " leave no voxel of the {slice} slice of this {} volume",
                        show_shape(&dims)
                    )
                ],
            ));
        }
        Ok(SliceRegion {
            slice: slice.axis,
            index,
            ranges: region,
        })
    }

    /// The axial slices (constant k) of the voxel box `block`, bottom to top: a block
    /// view's voxels, each once, in the file's order.
    pub fn block_slices(block: &[Range<usize>; 3]) -> Vec<SliceRegion> {
        block[2]
            .clone()
            .map(|k| SliceRegion {
                slice: SliceAxis::Axial,
                index: k,
                ranges: [block[0].clone(), block[1].clone(), k..k + 1],
            })
            .collect()
    }

    /// The voxels, i fastest (the file's order).
    pub fn voxels(&self) -> impl Iterator<Item = [usize; 3]> + '_ {
        let [ri, rj, rk] = self.ranges.clone();
        rk.flat_map(move |k| {
            let ri = ri.clone();
            rj.clone()
                .flat_map(move |j| ri.clone().map(move |i| [i, j, k]))
        })
    }

    /// The number of voxels in the region.
    pub fn len(&self) -> usize {
        self.ranges.iter().map(|r| r.len()).product()
    }

    /// Whether the ranges leave no voxel of the slice.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether `voxel` lies in this region.
    pub fn contains(&self, voxel: [usize; 3]) -> bool {
        self.ranges.iter().zip(voxel).all(|(r, v)| r.contains(&v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_slices_and_ranges() {
        let s: Slice = "coronal:3".parse().unwrap();
        assert_eq!((s.axis, s.index), (SliceAxis::Coronal, Some(3)));
        assert_eq!("axial".parse::<Slice>().unwrap(), Slice::default());
        assert_eq!("axial:mid".parse::<Slice>().unwrap(), Slice::default());
        let s: Slice = "sagittal:mid".parse().unwrap();
        assert_eq!((s.axis, s.index), (SliceAxis::Sagittal, None));
        for bad in [
            "transverse:1",
            "axial:-1",
            "axial:x",
            "axial:middle",
            "axial:",
        ] {
            assert!(bad.parse::<Slice>().is_err(), "{bad}");
        }
        let r: VoxelRanges = "1:4,:,5:".parse().unwrap();
        assert_eq!(r.axes[0], Some((Some(1), Some(4))));
        assert_eq!(r.axes[1], Some((None, None)));
        assert_eq!(r.axes[2], Some((Some(5), None)));
        for bad in ["1:4,2:3", "4:4,:,:", "1-4,:,:", "a:3,:,:"] {
            assert!(bad.parse::<VoxelRanges>().is_err(), "{bad}");
        }
        assert_eq!("mid".parse::<Slices>().unwrap(), Slices::default());
        let three: Slices = "1, 2,3".parse().unwrap();
        assert_eq!(three.indices, [Some(1), Some(2), Some(3)]);
        assert_eq!(
            three.slice(1),
            Slice {
                axis: SliceAxis::Coronal,
                index: Some(2)
            }
        );
        for bad in ["1,2", "1,2,x", "middle", "1,2,3,4"] {
            assert!(bad.parse::<Slices>().is_err(), "{bad}");
        }
    }

    /// A volume stored sagittally (i along world y, j along z, k along x) has its axial
    /// plane at constant j; a slightly oblique axial one keeps the identity.
    #[test]
    fn world_planes_find_their_voxel_axes() {
        use glam::DVec3;
        let sagittal_storage = DMat3::from_cols(2.0 * DVec3::Y, 2.0 * DVec3::Z, -3.0 * DVec3::X);
        let plane = |axis: SliceAxis, linear| axis.world_plane_in_voxels(linear);
        assert_eq!(
            plane(SliceAxis::Axial, sagittal_storage),
            SliceAxis::Coronal
        );
        assert_eq!(
            plane(SliceAxis::Coronal, sagittal_storage),
            SliceAxis::Sagittal
        );
        assert_eq!(
            plane(SliceAxis::Sagittal, sagittal_storage),
            SliceAxis::Axial
        );
        let oblique = DMat3::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.3);
        for axis in [SliceAxis::Sagittal, SliceAxis::Coronal, SliceAxis::Axial] {
            assert_eq!(plane(axis, oblique), axis);
        }
    }

    #[test]
    fn region_is_the_slice_cut_by_the_ranges() {
        let ranges: VoxelRanges = "1:3,:,0:100".parse().unwrap();
        let slice = Slice {
            axis: SliceAxis::Coronal,
            index: Some(2),
        };
        let region = SliceRegion::new([4, 5, 6], slice, &ranges, "v.nii").unwrap();
        assert_eq!(region.ranges, [1..3, 2..3, 0..6]);
        assert_eq!(region.len(), 12);
        assert_eq!(region.voxels().count(), 12);
        assert_eq!(region.voxels().next(), Some([1, 2, 0]));
        assert_eq!(region.voxels().nth(1), Some([2, 2, 0]));
        let middle =
            SliceRegion::new([4, 5, 6], Slice::default(), &Default::default(), "v").unwrap();
        assert_eq!(middle.ranges, [0..4, 0..5, 3..4]);
    }

    #[test]
    fn a_block_is_the_ranges_cut_to_the_volume_in_axial_slices() {
        let ranges: VoxelRanges = "1:3,:,2:100".parse().unwrap();
        let block = ranges.block([4, 5, 6], "v.nii").unwrap();
        assert_eq!(block, [1..3, 0..5, 2..6]);
        assert_eq!(show_block(&block), "1:3,0:5,2:6");
        let slices = SliceRegion::block_slices(&block);
        assert_eq!(slices.len(), 4);
        assert_eq!(
            slices.iter().map(SliceRegion::len).sum::<usize>(),
            2 * 5 * 4
        );
        let voxels: Vec<[usize; 3]> = slices.iter().flat_map(|s| s.voxels()).collect();
        assert_eq!(voxels.first(), Some(&[1, 0, 2]));
        assert_eq!(voxels.last(), Some(&[2, 4, 5]));
        let unique: std::collections::BTreeSet<_> = voxels.iter().collect();
        assert_eq!(unique.len(), voxels.len());
        let whole = VoxelRanges::default().block([4, 5, 6], "v.nii").unwrap();
        assert_eq!(whole, [0..4, 0..5, 0..6]);
        let outside: VoxelRanges = ":,:,6:9".parse().unwrap();
        let err = outside.block([4, 5, 6], "v.nii").unwrap_err().to_string();
        assert_eq!(
            err,
            "v.nii: voxels: the ranges of voxels leave no voxel of this 4x5x6 volume"
        );
    }

    #[test]
    fn out_of_range_index_and_empty_regions_are_errors() {
        let slice = Slice {
            axis: SliceAxis::Axial,
            index: Some(6),
        };
        let err = SliceRegion::new([4, 5, 6], slice, &Default::default(), "v.nii")
            .unwrap_err()
            .to_string();
        assert!(err.contains("v.nii") && err.contains("dim[3]"), "{err}");
        let ranges: VoxelRanges = "10:12,:,:".parse().unwrap();
        let err = SliceRegion::new([4, 5, 6], Slice::default(), &ranges, "v.nii")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("v.nii: voxels: "), "{err}");
        assert!(!err.contains("--"), "{err}");
        // Text the library cannot read names the setting.
        for (err, setting) in [
            ("diagonal".parse::<Slice>().unwrap_err(), Setting::Slice),
            ("1,2".parse::<Slices>().unwrap_err(), Setting::Slices),
            ("1:2,3".parse::<VoxelRanges>().unwrap_err(), Setting::Voxels),
        ] {
            assert_eq!(err.setting_of(), Some(setting), "{err}");
            assert!(!err.to_string().contains("--"), "{err}");
        }
    }
}
