//! Peak images (`--peaks`, `--peak-values`) and the capsules of a view's slices.
//!
//! Two layouts, told apart by what the user gives, never guessed from the values:
//! - without values (MRtrix `sh2peaks`, `glyphcast peaks`): 3 N values per voxel, each
//!   peak's direction times its amplitude; NaN (or a zero vector) where a voxel has
//!   fewer peaks. A 4D image [x, y, z, 3N], or 5D [x, y, z, N, 3].
//! - with a values image (DIPY's `peaks_dirs` with `peak_values`): unit directions, 4D
//!   [x, y, z, 3N] or 5D [x, y, z, N, 3] as DIPY's arrays are saved, and amplitudes
//!   [x, y, z, N]; a peak is absent where its value is not positive or its direction is
//!   zero or NaN. Directions that are not unit vectors are refused: the file is then
//!   probably in the first layout.
//!
//! Directions are in the frame a coefficient volume would be in ([`CoefficientFrame`]):
//! voxel axes for NIfTI (DIPY's and `glyphcast peaks`' frame for a NIfTI ODF), scanner
//! axes for MRtrix unless the header says `glyphcast_frame: voxel`; the peaks frame
//! setting names another (MRtrix's `sh2peaks` writes scanner axes into a NIfTI too). Voxel-frame
//! directions are turned into the world by the affine's orthogonal factor R, as the SH
//! glyphs are (`reorient`): a peak found on the glyph's own series lies along the drawn
//! lobe. The peaks' grid must be the glyph volume's (dimensions and affine).
use std::path::Path;
use std::str::FromStr;
use std::sync::Arc;

use glam::{DMat3, DVec3};
use ndarray::ArrayD;

use super::input::{CoefficientFrame, Mask, show_shape};
use super::selection::SliceRegion;
use crate::io::image::{Image, read_image, trimmed_shape};
use crate::io::nifti::VoxelToWorld;
use glyphcast::camera::{Camera, Projection};
use glyphcast::error::quoted;
use glyphcast::glyph::capsule::Capsule;
use glyphcast::render::peaks::{PeakSegment, PeakSet};
use glyphcast::{Error, Result, Setting};

/// Default world half length of the longest peak, as a fraction of the smallest voxel
/// size: the longest peak spans its voxel (glyphs span 0.9 of one by default).
pub const DEFAULT_PEAKS_SCALE_FRACTION: f64 = 0.5;
/// Default width of a peak, in pixels.
pub const DEFAULT_PEAKS_WIDTH: f64 = 2.0;
/// How far from 1 the length of a direction in a DIPY layout may be.
const UNIT_TOLERANCE: f64 = 1e-3;
/// Largest affine difference (a fraction of the smallest voxel size) between the peaks'
/// grid and the glyphs' that still counts as the same grid (float32 headers).
const GRID_TOLERANCE: f64 = 1e-3;

/// How a peak is coloured.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum PeaksColor {
    /// RGB = |x|, |y|, |z| of the world direction (mrview's and FURY's default).
    #[default]
    Direction,
    /// One sRGB colour, channels 0 to 1.
    Uniform([f64; 3]),
}

/// How peak lengths follow amplitudes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PeaksNorm {
    /// Lengths proportional to amplitudes; the longest drawn gets the scale.
    #[default]
    Global,
    /// Every peak the scale, whatever its amplitude.
    Unit,
    /// Half length = amplitude times the scale.
    None,
}

/// How peaks are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakStyle {
    /// How each peak is coloured.
    pub color: PeaksColor,
    /// How peak lengths follow the amplitudes.
    pub norm: PeaksNorm,
    /// World half length of the longest peak (with [`PeaksNorm::None`], per unit
    /// amplitude); default [`DEFAULT_PEAKS_SCALE_FRACTION`] of the smallest voxel size.
    pub scale: Option<f64>,
    /// Diameter in pixels of the image (orthographic views: everywhere; perspective:
    /// at the camera's target).
    pub width: f64,
}

impl Default for PeakStyle {
    fn default() -> Self {
        PeakStyle {
            color: PeaksColor::default(),
            norm: PeaksNorm::default(),
            scale: None,
            width: DEFAULT_PEAKS_WIDTH,
        }
    }
}

impl FromStr for PeaksColor {
    type Err = Error;

    /// `direction`, a name (white, black, grey, red, green, blue, yellow, cyan,
    /// magenta), `#rrggbb` or `r,g,b` (0 to 255 each, sRGB as in the PNG).
    fn from_str(text: &str) -> Result<Self> {
        let bytes: Option<[u8; 3]> = match text {
            "direction" => return Ok(PeaksColor::Direction),
            "white" => Some([255, 255, 255]),
            "black" => Some([0, 0, 0]),
            "grey" | "gray" => Some([128, 128, 128]),
            "red" => Some([255, 0, 0]),
            "green" => Some([0, 255, 0]),
            "blue" => Some([0, 0, 255]),
            "yellow" => Some([255, 255, 0]),
            "cyan" => Some([0, 255, 255]),
            "magenta" => Some([255, 0, 255]),
            _ => glyphcast::render::settings::parse_rgb8(text),
        };
        bytes
            .map(|b| PeaksColor::Uniform(b.map(|v| f64::from(v) / 255.0)))
            .ok_or_else(|| {
                Error::setting_value(
                    Setting::PeaksColor,
                    format!("'{}'", quoted(text)),
                    "expected direction, a colour name, #rrggbb or r,g,b (0-255)",
                )
            })
    }
}

impl FromStr for PeaksNorm {
    type Err = Error;

    fn from_str(text: &str) -> Result<Self> {
        match text {
            "global" => Ok(PeaksNorm::Global),
            "unit" => Ok(PeaksNorm::Unit),
            "none" => Ok(PeaksNorm::None),
            _ => Err(Error::setting_value(
                Setting::PeaksNorm,
                format!("'{}'", quoted(text)),
                "expected global, unit or none",
            )),
        }
    }
}

impl PeakStyle {
    /// Checks scale and width.
    pub fn validate(&self) -> Result<()> {
        if let Some(scale) = self.scale
            && !(scale.is_finite() && scale > 0.0)
        {
            return Err(Error::setting_value(
                Setting::PeaksScale,
                scale,
                "must be a positive number",
            ));
        }
        if !(self.width.is_finite() && self.width > 0.0 && self.width <= 100.0) {
            return Err(Error::setting_value(
                Setting::PeaksWidth,
                self.width,
                "must be a number of pixels above 0, at most 100",
            ));
        }
        Ok(())
    }
}

/// A peak image: per voxel up to `count` peaks, each a world-or-voxel-frame direction
/// and an amplitude.
#[derive(Clone, Debug)]
pub struct PeakVolume {
    /// The directions' file, for messages.
    pub file: String,
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// Voxel indices to world coordinates, from the directions' file.
    pub voxel_to_world: VoxelToWorld,
    /// The frame of the directions.
    pub frame: CoefficientFrame,
    /// Peaks per voxel.
    pub count: usize,
    /// Per voxel (i fastest), per peak: unit direction and amplitude; amplitude 0 where
    /// there is no peak.
    peaks: Vec<([f64; 3], f64)>,
}

/// Reads a peak image, with the amplitudes of a DIPY layout if `values` is given, its
/// directions in `frame` if given, else in the file's own ([`CoefficientFrame::of_image`]).
pub fn load_peaks(
    path: &Path,
    values: Option<&Path>,
    frame: Option<CoefficientFrame>,
) -> Result<PeakVolume> {
    let values = values.map(read_image).transpose()?;
    let image = read_image(path)?;
    super::recorded::check_content(&image, super::recorded::RecordedContent::Peaks)?;
    PeakVolume::from_images(image, values, frame)
}

/// The values of a peak image and where they lie, from a file or from memory.
#[derive(Clone, Debug)]
pub struct PeakArray {
    /// The file or the argument, for messages.
    pub file: String,
    /// [x, y, z, 3N], [x, y, z, N, 3] (directions) or [x, y, z, N] (values).
    pub data: ArrayD<f64>,
    /// Voxel indices to world coordinates of the values' grid.
    pub voxel_to_world: VoxelToWorld,
}

impl From<Image> for PeakArray {
    fn from(image: Image) -> Self {
        PeakArray {
            file: image.file,
            data: image.data,
            voxel_to_world: image.voxel_to_world,
        }
    }
}

impl PeakArray {
    /// The shape with trailing axes of size 1 dropped down to `rank` entries (as
    /// [`Image::shape`]).
    fn shape(&self, rank: usize) -> Vec<usize> {
        trimmed_shape(self.data.shape(), rank)
    }
}

impl PeakVolume {
    /// The peaks of an image read with [`read_image`] (see the module's layouts), in
    /// `frame` if given, else the file's own ([`CoefficientFrame::of_image`]).
    pub fn from_images(
        image: Image,
        values: Option<Image>,
        frame: Option<CoefficientFrame>,
    ) -> Result<PeakVolume> {
        let frame = match frame {
            Some(frame) => frame,
            None => CoefficientFrame::of_image(&image)?,
        };
        PeakVolume::from_arrays(image.into(), values.map(PeakArray::from), frame)
    }

    /// The peaks of `directions` (the layouts of the module), with the amplitudes of a
    /// DIPY layout if `values` is given, their directions in `frame`.
    pub fn from_arrays(
        image: PeakArray,
        values: Option<PeakArray>,
        frame: CoefficientFrame,
    ) -> Result<PeakVolume> {
        let (dims, count, vector) = directions(&image)?;
        let amplitude: Box<dyn Fn([usize; 3], usize) -> f64> = match &values {
            None => Box::new(|_, _| 1.0),
            Some(values) => {
                check_values(values, &image, dims, count)?;
                Box::new(|v, p| at(values, &[v[0], v[1], v[2], p]))
            }
        };
        let mut peaks = Vec::with_capacity(dims.iter().product::<usize>() * count);
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    for p in 0..count {
                        let v = vector([i, j, k], p);
                        let length = v.length();
                        let present = length.is_finite() && length > 0.0;
                        let peak = match &values {
                            None if present => ((v / length).to_array(), length),
                            None => ([0.0; 3], 0.0),
                            Some(_) => {
                                let a = amplitude([i, j, k], p);
                                if !(present && a.is_finite() && a > 0.0) {
                                    ([0.0; 3], 0.0)
                                } else if (length - 1.0).abs() > UNIT_TOLERANCE {
                                    return Err(Error::input(
                                        &image.file,
                                        "data",
                                        glyphcast::message![
                                            format!(
                                                "peak {p} of voxel ({i}, {j}, {k}) has length \
                                             {length:.4}: with "
                                            ),
                                            Setting::PeakValues,
                                            " the directions are DIPY's \
                                             unit vectors; a file of direction times \
                                             amplitude (MRtrix sh2peaks, glyphcast peaks) \
                                             goes without ",
                                            Setting::PeakValues
                                        ],
                                    ));
                                } else {
                                    ((v / length).to_array(), a)
                                }
                            }
                        };
                        peaks.push(peak);
                    }
                }
            }
        }
        if peaks.iter().all(|(_, a)| *a == 0.0) {
            let what = match &values {
                None => "every value is NaN or zero".to_string(),
                Some(v) => format!("no positive value in {} goes with a direction", v.file),
            };
            return Err(Error::input(
                &image.file,
                "data",
                format!("no peak anywhere: {what}"),
            ));
        }
        drop(vector);
        Ok(PeakVolume {
            file: image.file,
            dims,
            voxel_to_world: image.voxel_to_world,
            frame,
            count,
            peaks,
        })
    }

    /// The peaks of voxel (i, j, k): unit direction (in [`PeakVolume::frame`]) and
    /// amplitude, absent ones left out.
    pub fn voxel_peaks(&self, voxel: [usize; 3]) -> impl Iterator<Item = (DVec3, f64)> + '_ {
        let [i, j, k] = voxel;
        let start = ((k * self.dims[1] + j) * self.dims[0] + i) * self.count;
        self.peaks[start..start + self.count]
            .iter()
            .filter(|(_, a)| *a > 0.0)
            .map(|(d, a)| (DVec3::from_array(*d), *a))
    }

    /// Refuses a peak image on another grid than the glyph volume `file` of `dims`
    /// placed by `map`.
    pub fn check_grid(&self, file: &str, dims: [usize; 3], map: &VoxelToWorld) -> Result<()> {
        if self.dims != dims {
            return Err(Error::input(
                &self.file,
                "dim",
                format!(
                    "the peaks' grid is {} voxels and {file}'s is {}: peaks are drawn on the \
                     glyphs' voxels",
                    show_shape(&self.dims),
                    show_shape(&dims)
                ),
            ));
        }
        let tolerance = GRID_TOLERANCE * map.voxel_sizes().min_element();
        let a = self.voxel_to_world.affine.to_cols_array();
        let b = map.affine.to_cols_array();
        let worst = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        if worst.is_nan() || worst > tolerance {
            return Err(Error::input(
                &self.file,
                "affine",
                format!(
                    "the peaks' voxel-to-world affine differs from {file}'s by up to {worst:.4} \
                     (more than {tolerance:.2e}): the peaks are not on the glyphs' grid"
                ),
            ));
        }
        Ok(())
    }

    /// The world map of the directions: R, the affine's orthogonal factor, for voxel-frame
    /// ones, the identity for world-frame ones.
    fn to_world(&self) -> Result<DMat3> {
        if self.frame == CoefficientFrame::World {
            return Ok(DMat3::IDENTITY);
        }
        self.voxel_to_world.orthogonal_factor().ok_or_else(|| {
            Error::input(
                &self.file,
                "affine",
                "the polar decomposition of the affine did not converge",
            )
        })
    }
}

/// What a view's peaks are drawn from.
#[derive(Clone, Debug)]
pub struct ViewPeaks {
    /// The peak image (shared by a montage's panels and the viewer's moves).
    pub volume: Arc<PeakVolume>,
    /// Colour, length normalisation and scale of the capsules.
    pub style: PeakStyle,
}

/// The capsules of `peaks` in the voxels of `regions` (each voxel once; those `mask`
/// keeps, if any), seen by `camera` on an image `image_height` pixels high (which turns
/// the width in pixels into a world radius).
pub fn peak_set(
    peaks: &ViewPeaks,
    regions: &[SliceRegion],
    mask: Option<&Mask>,
    camera: &Camera,
    image_height: u32,
) -> Result<PeakSet> {
    let volume = &peaks.volume;
    let style = peaks.style;
    style.validate()?;
    let rotation = volume.to_world()?;
    let map = &volume.voxel_to_world;
    let mut found: Vec<(DVec3, DVec3, f64)> = Vec::new();
    for (n, region) in regions.iter().enumerate() {
        for voxel in region.voxels() {
            if regions[..n].iter().any(|earlier| earlier.contains(voxel)) {
                continue;
            }
            if mask.is_some_and(|m| !m.keeps(voxel)) {
                continue;
            }
            let center = map.voxel_center(DVec3::from_array(voxel.map(|v| v as f64)));
            for (direction, amplitude) in volume.voxel_peaks(voxel) {
                found.push((center, (rotation * direction).normalize(), amplitude));
            }
        }
    }
    let scale = style
        .scale
        .unwrap_or_else(|| DEFAULT_PEAKS_SCALE_FRACTION * map.voxel_sizes().min_element());
    let largest = found.iter().map(|f| f.2).fold(0.0, f64::max);
    let radius = 0.5 * style.width * pixel_size(camera, image_height);
    let segments = found
        .into_iter()
        .map(|(center, direction, amplitude)| {
            let half = match style.norm {
                PeaksNorm::Global => scale * amplitude / largest,
                PeaksNorm::Unit => scale,
                PeaksNorm::None => scale * amplitude,
            };
            let color = match style.color {
                PeaksColor::Direction => direction.abs().to_array(),
                PeaksColor::Uniform(rgb) => rgb,
            };
            PeakSegment {
                capsule: Capsule::through(center, half * direction, radius),
                color,
            }
        })
        .collect();
    Ok(PeakSet {
        segments,
        lines: Vec::new(),
    })
}

/// World size of one pixel: everywhere for an orthographic camera, at the target for a
/// perspective one.
pub fn pixel_size(camera: &Camera, image_height: u32) -> f64 {
    let height = match camera.projection {
        Projection::Orthographic { height } => height,
        Projection::Perspective { fov_y_deg } => {
            2.0 * (0.5 * fov_y_deg.to_radians()).tan() * (camera.target - camera.eye).length()
        }
    };
    height / f64::from(image_height.max(1))
}

/// A grid, a peak count, and the vectors by voxel and peak.
type Directions<F> = ([usize; 3], usize, F);

/// The grid and peak count of a directions image, and its vectors by voxel and peak.
fn directions(image: &PeakArray) -> Result<Directions<impl Fn([usize; 3], usize) -> DVec3 + '_>> {
    let shape = image.shape(4);
    let (dims, count, five) = match shape.len() {
        4 if shape[3].is_multiple_of(3) => ([shape[0], shape[1], shape[2]], shape[3] / 3, false),
        4 => {
            return Err(Error::input(
                &image.file,
                "dim[4]",
                format!(
                    "{} volumes is not a multiple of 3: a peak image holds x, y, z per peak \
                     ({})",
                    shape[3],
                    show_shape(&shape)
                ),
            ));
        }
        5 if shape[4] == 3 => ([shape[0], shape[1], shape[2]], shape[3], true),
        _ => {
            return Err(Error::input(
                &image.file,
                "dim",
                format!(
                    "a {}D image ({}) where peaks are 4D [x, y, z, 3N] or 5D [x, y, z, N, 3]",
                    shape.len(),
                    show_shape(&shape)
                ),
            ));
        }
    };
    let vector = move |v: [usize; 3], p: usize| {
        DVec3::from_array(std::array::from_fn(|c| {
            let index = if five {
                vec![v[0], v[1], v[2], p, c]
            } else {
                vec![v[0], v[1], v[2], 3 * p + c]
            };
            at(image, &index)
        }))
    };
    Ok((dims, count, vector))
}

/// The value at `index` (trailing axes of size 1 at 0); NaN outside the data.
fn at(image: &PeakArray, index: &[usize]) -> f64 {
    let rank = image.data.ndim();
    let mut full = vec![0usize; rank];
    for (slot, i) in full.iter_mut().zip(index) {
        *slot = *i;
    }
    image.data.get(full.as_slice()).copied().unwrap_or(f64::NAN)
}

/// A values image must be [x, y, z, N] on the directions' grid.
fn check_values(
    values: &PeakArray,
    directions: &PeakArray,
    dims: [usize; 3],
    count: usize,
) -> Result<()> {
    let shape = values.shape(4);
    let expected = [dims[0], dims[1], dims[2], count];
    let matches = shape.len() == 4 && shape[..] == expected[..]
        || count == 1 && shape.len() == 3 && shape[..] == dims[..];
    if !matches {
        return Err(Error::input(
            &values.file,
            "dim",
            format!(
                "the peak values are {} where {} peaks of {} need {}",
                show_shape(&shape),
                count,
                directions.file,
                show_shape(&expected)
            ),
        ));
    }
    let a = values.voxel_to_world.affine;
    let b = directions.voxel_to_world.affine;
    let tolerance = GRID_TOLERANCE * directions.voxel_to_world.voxel_sizes().min_element();
    if !a.abs_diff_eq(b, tolerance) {
        return Err(Error::input(
            &values.file,
            "affine",
            format!(
                "the peak values' voxel-to-world affine is not that of {}",
                directions.file
            ),
        ));
    }
    Ok(())
}
