//! Coefficient volumes and masks read from NIfTI-1 or MRtrix files (`io::image`), checked against what the
//! user said they hold: a 4D volume [x, y, z, N] whose N matches the SH band or the
//! tensor layout, a 3D mask. Every mismatch names the file and the dimension.
//!
//! A volume also knows the frame its coefficients are in ([`CoefficientFrame`]): NIfTI
//! files are taken in voxel axes (as DIPY writes them), MRtrix files in scanner axes (as
//! MRtrix stores, mrview draws and `glyphcast fit` writes them) unless their header says
//! `glyphcast_frame: voxel`.
use std::fmt;
use std::path::Path;
use std::str::FromStr;

use ndarray::{Array3, Array4, ArrayD, Axis, Ix3, Ix4};

use crate::io::image::{Image, ImageHeader, read_image};
use crate::io::nifti::VoxelToWorld;
use crate::volume::PeakVolume;
use glyphcast::glyph::TensorLayout;
use glyphcast::glyph::sh;
use glyphcast::glyph::tensor_order::{DTI_COUNT, OrderEvidence, TensorOrder, negate_x};
use glyphcast::scene::{GlyphKind, ShBasis};
use glyphcast::{Error, Result, Setting};

/// Highest SH band and tensor order of the scene format.
/// Highest tensor order or SH band of a volume (the table in [`glyphcast::catalog`]).
pub const MAX_ORDER: u32 = glyphcast::catalog::MAX_SYMMETRIC_ORDER;

/// What the user says a volume holds; the SH band is read off the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeKind {
    /// Spherical-harmonic coefficients, even bands only.
    Sh {
        /// The basis convention the coefficients are stored in.
        basis: ShBasis,
        /// DIPY's `legacy=True` variant of the basis (no sqrt2 factors, other phases).
        legacy: bool,
    },
    /// Cartesian tensor coefficients of this order and symmetry.
    Tensor(TensorLayout),
}

/// The axes a volume's coefficients are expressed in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CoefficientFrame {
    /// The image's voxel axes (DIPY, FSL): glyphs are turned by the affine's orthogonal
    /// factor on the way to the world.
    #[default]
    Voxel,
    /// Scanner (world) axes (MRtrix): glyphs are drawn as stored; only their centres go
    /// through the affine.
    World,
}

/// The header key in which `glyphcast fit` records the frame of a `.mif` it writes.
const FRAME_KEY: &str = "glyphcast_frame";

/// A 4D volume of glyph coefficients: one coefficient list per voxel.
#[derive(Clone, Debug)]
pub struct Volume {
    /// The file it came from, for messages.
    pub file: String,
    /// Voxels along i, j, k.
    pub dims: [usize; 3],
    /// The glyph kind of every voxel (for SH, the band deduced from the file).
    pub kind: GlyphKind,
    /// Voxel indices to world coordinates (the file's sform, qform or MRtrix transform).
    pub voxel_to_world: VoxelToWorld,
    /// The frame of the coefficients: the file's default, or what the user said.
    pub frame: CoefficientFrame,
    /// Notes for the user about how the file was read (a basis name that other tools
    /// read otherwise, a 6-volume SH file whose name suggests a tensor); the front ends
    /// print them with the figure.
    pub notes: Vec<glyphcast::error::Message>,
    /// Shape [x, y, z, coefficients].
    data: Array4<f64>,
    /// No glyphs: the volume stands for a peak image's grid ([`Volume::grid_of_peaks`]).
    peaks_grid: bool,
}

/// Which voxels a mask keeps: nonzero values (NaN counts as zero).
#[derive(Clone, Debug)]
pub struct Mask {
    /// The file it came from, for messages.
    pub file: String,
    /// Voxels along i, j, k; they must equal the volume's.
    pub dims: [usize; 3],
    keep: Array3<bool>,
}

/// Reads a coefficient volume and checks it against `kind`.
pub fn load_volume(path: &Path, kind: VolumeKind) -> Result<Volume> {
    Volume::from_image(read_image(path)?, kind)
}

/// Reads a 3D mask ([x, y, z] or [x, y, z, 1]).
pub fn load_mask(path: &Path) -> Result<Mask> {
    Mask::from_image(read_image(path)?)
}

impl Volume {
    /// The SH basis the coefficients are read in, with its variant, as the front ends'
    /// summaries print it ("descoteaux07, legacy"; "tournier07"); `None` for tensors.
    pub fn basis_summary(&self) -> Option<String> {
        match self.kind {
            GlyphKind::Sh { basis, legacy, .. } => Some(if legacy {
                format!("{}, legacy", basis.name())
            } else {
                basis.name().to_owned()
            }),
            _ => None,
        }
    }

    /// A volume from values of shape [x, y, z, coefficients]; `file` names errors.
    pub fn new(
        file: impl Into<String>,
        data: Array4<f64>,
        kind: VolumeKind,
        voxel_to_world: VoxelToWorld,
    ) -> Result<Self> {
        let file = file.into();
        let shape = data.shape();
        let dims = [shape[0], shape[1], shape[2]];
        let kind = glyph_kind(&file, kind, shape[3])?;
        Ok(Self {
            file,
            dims,
            kind,
            voxel_to_world,
            frame: CoefficientFrame::Voxel,
            notes: Vec::new(),
            data,
            peaks_grid: false,
        })
    }

    /// A volume without glyphs that stands for the grid of `peaks` (file, dimensions,
    /// affine): a view of peaks alone is selected and framed as one of this volume, and
    /// draws no glyph.
    pub fn grid_of_peaks(peaks: &PeakVolume) -> Result<Self> {
        let [x, y, z] = peaks.dims;
        let kind = VolumeKind::Sh {
            basis: ShBasis::Tournier07,
            legacy: false,
        };
        let data = Array4::zeros((x, y, z, 1));
        let mut volume = Self::new(&peaks.file, data, kind, peaks.voxel_to_world)?;
        volume.peaks_grid = true;
        Ok(volume)
    }

    /// Whether the volume only stands for a peak image's grid.
    pub fn is_peaks_grid(&self) -> bool {
        self.peaks_grid
    }

    /// The volume of an image read with [`read_image`], checked against `kind`, in the
    /// image's default frame ([`CoefficientFrame::of_image`]).
    pub fn from_image(image: Image, kind: VolumeKind) -> Result<Self> {
        let frame = CoefficientFrame::of_image(&image)?;
        check_four_d(&image)?;
        let data = squeeze(image.data, 4)
            .into_dimensionality::<Ix4>()
            .map_err(|err| Error::input(&image.file, "dim", err.to_string()))?;
        let mut volume = Self::new(image.file, data, kind, image.voxel_to_world)?;
        volume.frame = frame;
        Ok(volume)
    }

    /// Coefficients per voxel.
    pub fn coefficient_count(&self) -> usize {
        self.data.shape()[3]
    }

    /// The coefficients of voxel (i, j, k), in glyphcast's order, without a copy (for
    /// passes over every voxel).
    pub fn coefficients_view(&self, voxel: [usize; 3]) -> ndarray::ArrayView1<'_, f64> {
        let [i, j, k] = voxel;
        self.data.slice(ndarray::s![i, j, k, ..])
    }

    /// Each voxel's six DTI entries, stored in `stored` order, put in glyphcast's order
    /// and in the voxel axes (FSL's frame negates x on an image with a positive
    /// determinant: [`TensorOrder::negates_x`]); the caller has checked that the volume
    /// holds symmetric order-2 tensors.
    pub fn reorder_tensors(&mut self, stored: TensorOrder) {
        let negates_x = stored.negates_x(self.voxel_to_world.linear().determinant());
        if (stored.is_glyphcast() && !negates_x) || self.coefficient_count() != DTI_COUNT {
            return;
        }
        for mut lane in self.data.lanes_mut(Axis(3)) {
            let values: [f64; DTI_COUNT] = std::array::from_fn(|k| lane[k]);
            let mut entries = stored.to_glyphcast(&values);
            if negates_x {
                negate_x(&mut entries);
            }
            for (out, value) in lane.iter_mut().zip(entries) {
                *out = value;
            }
        }
    }

    /// How many of the volume's six-entry tensors each stored order makes positive
    /// definite (empty for other coefficient counts).
    pub fn order_evidence(&self) -> OrderEvidence {
        let mut evidence = OrderEvidence::default();
        if self.coefficient_count() == DTI_COUNT {
            for lane in self.data.lanes(Axis(3)) {
                evidence.add(&std::array::from_fn(|k| lane[k]));
            }
        }
        evidence
    }

    /// The coefficients of voxel (i, j, k), in glyphcast's order.
    pub fn coefficients(&self, voxel: [usize; 3]) -> Vec<f64> {
        let [i, j, k] = voxel;
        (0..self.coefficient_count())
            .map(|c| self.data[[i, j, k, c]])
            .collect()
    }
}

/// Err, naming the file's `dim`, unless `image` is 4D [x, y, z, coefficients] (trailing
/// axes of length 1 aside).
pub fn check_four_d(image: &Image) -> Result<()> {
    let shape = image.shape(4);
    if shape.len() == 4 {
        return Ok(());
    }
    Err(Error::input(
        &image.file,
        "dim",
        format!(
            "a {}D image ({}) where a 4D volume [x, y, z, coefficients] is needed",
            shape.len(),
            show_shape(&shape)
        ),
    ))
}

impl CoefficientFrame {
    /// The frame a file's coefficients are taken in when the user does not say: voxel
    /// axes for NIfTI, scanner axes for MRtrix unless its `glyphcast_frame` key says
    /// otherwise.
    pub fn of_image(image: &Image) -> Result<Self> {
        let ImageHeader::Mrtrix(header) = &image.header else {
            return Ok(CoefficientFrame::Voxel);
        };
        match header.other.iter().find(|(key, _)| key == FRAME_KEY) {
            None => Ok(CoefficientFrame::World),
            Some((_, value)) => value
                .trim()
                .parse()
                .map_err(|err: Error| Error::input(&image.file, FRAME_KEY, err.to_string())),
        }
    }

    /// The name used by `--frame` and in the `.mif` key.
    pub fn name(self) -> &'static str {
        match self {
            CoefficientFrame::Voxel => "voxel",
            CoefficientFrame::World => "world",
        }
    }
}

impl fmt::Display for CoefficientFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for CoefficientFrame {
    type Err = Error;

    /// `voxel` or `world`.
    fn from_str(text: &str) -> Result<Self> {
        match text {
            "voxel" => Ok(CoefficientFrame::Voxel),
            "world" => Ok(CoefficientFrame::World),
            _ => Err(Error::setting_value(
                Setting::Frame,
                format!("'{}'", glyphcast::error::quoted(text)),
                "expected voxel or world",
            )),
        }
    }
}

impl Mask {
    /// A mask from values of shape [x, y, z]; `file` names errors.
    pub fn new(file: impl Into<String>, values: &Array3<f64>) -> Self {
        let shape = values.shape();
        Self {
            file: file.into(),
            dims: [shape[0], shape[1], shape[2]],
            keep: values.mapv(|v| v != 0.0 && !v.is_nan()),
        }
    }

    fn from_image(image: Image) -> Result<Self> {
        let shape = image.shape(3);
        if shape.len() != 3 {
            return Err(Error::input(
                &image.file,
                "dim",
                format!(
                    "a {}D image ({}) where a 3D mask is needed",
                    shape.len(),
                    show_shape(&shape)
                ),
            ));
        }
        let values = squeeze(image.data, 3)
            .into_dimensionality::<Ix3>()
            .map_err(|err| Error::input(&image.file, "dim", err.to_string()))?;
        Ok(Self::new(image.file, &values))
    }

    /// Whether voxel (i, j, k) is kept; the caller has checked the shape.
    pub fn keeps(&self, voxel: [usize; 3]) -> bool {
        self.keep.get(voxel).copied().unwrap_or(false)
    }
}

/// Drops trailing axes of length 1 down to `rank` axes and pads to `rank` axes, as
/// [`Image::shape`] does (the caller has checked that this leaves `rank` axes).
fn squeeze(mut data: ArrayD<f64>, rank: usize) -> ArrayD<f64> {
    while data.ndim() > rank && data.shape().last() == Some(&1) {
        let last = Axis(data.ndim() - 1);
        data = data.index_axis_move(last, 0);
    }
    while data.ndim() < rank {
        data.insert_axis_inplace(Axis(data.ndim()));
    }
    data
}

pub(crate) fn show_shape(shape: &[usize]) -> String {
    let parts: Vec<String> = shape.iter().map(usize::to_string).collect();
    parts.join("x")
}

/// The glyph kind of a volume with `count` coefficients per voxel, or an error naming
/// the file's fourth dimension.
fn glyph_kind(file: &str, kind: VolumeKind, count: usize) -> Result<GlyphKind> {
    match kind {
        VolumeKind::Sh { basis, legacy } => {
            let band = (0..=MAX_ORDER)
                .step_by(2)
                .find(|&band| sh::sh_count(band) == count);
            let Some(band) = band else {
                let valid: Vec<String> = (0..=MAX_ORDER)
                    .step_by(2)
                    .map(|band| format!("{} (L={band})", sh::sh_count(band)))
                    .collect();
                return Err(Error::input(
                    file,
                    "dim[4]",
                    format!(
                        "{count} coefficients per voxel is not (L+1)(L+2)/2 for an even SH band \
                         L <= {MAX_ORDER}; expected one of {}",
                        valid.join(", ")
                    ),
                ));
            };
            Ok(GlyphKind::Sh {
                band,
                basis,
                legacy,
            })
        }
        VolumeKind::Tensor(layout) => {
            if !(1..=MAX_ORDER).contains(&layout.order) {
                return Err(Error::setting_value(
                    Setting::Order,
                    layout.order,
                    format!("must be in 1 to {MAX_ORDER}"),
                ));
            }
            let expected = layout.coefficient_count();
            if count != expected {
                return Err(Error::input(
                    file,
                    "dim[4]",
                    format!(
                        "{count} coefficients per voxel, but a {} needs {expected}",
                        GlyphKind::Tensor(layout)
                    ),
                ));
            }
            Ok(GlyphKind::Tensor(layout))
        }
    }
}
