//! A volume figure as the front ends ask for it: the CLI's volume flags and the Python
//! module's keyword arguments, as text and numbers, turned into the volume's kind,
//! [`VolumeOptions`] and the view or montage (`figure`) with one set of defaults and
//! checks. A value that is refused, or options that do not go together, are errors that
//! name the [`Setting`]s; each front end spells them (`--slice`, `slice=`).
use std::path::{Path, PathBuf};

use super::build::VolumeOptions;
use super::framing::{ImageRequest, ViewProjection};
use super::input::check_four_d;
use super::input::{CoefficientFrame, Mask, Volume, VolumeKind};
use super::recorded::{
    OrderSource, RecordedContent, check_content, check_variant_named, has_dti_entries,
    resolve_basis, resolve_tensor_order,
};
use super::selection::Slice;
use super::underlay::UnderlayPlacement;
use crate::io::image::{Image, ImageHeader, read_image};
use crate::io::nifti::VoxelToWorld;
use crate::io::tracks::select::subsample;
use crate::io::tracks::{Tractogram, read_tractogram};
use crate::setting::DmriSetting;
use crate::volume::peaks::{DEFAULT_PEAKS_WIDTH, PeakStyle, PeakVolume, ViewPeaks, load_peaks};
use crate::volume::tracks::{
    DEFAULT_TRACKS_RADIUS_MM, ScalarColor, TrackStyle, TracksColor, ViewTracks, scalar_request,
};
use glyphcast::error::quoted;
use glyphcast::glyph::ellipsoid::ELLIPSOID_LAYOUT;
use glyphcast::glyph::sh::parse_basis_choice;
use glyphcast::glyph::tensor_order::TensorOrder;
use glyphcast::glyph::{GlyphShape, Symmetry, TensorLayout};
use glyphcast::render::underlay::UnderlayVolume;
use glyphcast::scene::{GlyphKind, ShBasis};
use glyphcast::{Error, Result, Setting};
use std::sync::Arc;

/// The most panels of a montage ([`Setting::Views`], [`Setting::Lightbox`]).
pub const MAX_PANELS: usize = 64;

/// What a volume's coefficients are, as the front end was asked: SH coefficients
/// (`--sh`, `render_sh`) or Cartesian tensor coefficients (`--tensor`, `render_tensor`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coefficients {
    /// A real SH series per voxel.
    Sh,
    /// A tensor per voxel, of the order the request gives.
    Tensor,
}

/// An image a request names: a file to read, or one the caller holds in memory (placed
/// in world space by an affine it was given).
#[derive(Clone, Debug)]
pub enum ImageSource<T> {
    /// A NIfTI or MRtrix file, read with the one image reader.
    File(PathBuf),
    /// Values in memory.
    Memory(T),
}

/// The volume options, unparsed; `None` (or `false`) is the default. Each field is the
/// [`Setting`] of the same name.
#[derive(Clone, Debug, Default)]
pub struct VolumeRequest {
    /// tournier07, descoteaux07, mrtrix, dipy or dipy-new.
    pub basis: Option<String>,
    /// `basis` even where the file records another.
    pub force_basis: bool,
    /// voxel or world.
    pub frame: Option<String>,
    /// The variant of `basis`: `Some(true)` the legacy one, `Some(false)` the
    /// non-legacy one, `None` the name's own (an alias's, else non-legacy).
    pub legacy: Option<bool>,
    /// Draw SH bands up to this one.
    pub lmax: Option<u32>,
    /// The tensor order of a tensor volume.
    pub order: Option<u32>,
    /// A tensor volume holds all 3^N entries.
    pub nonsymmetric: bool,
    /// The stored order of a DTI volume's six entries: glyphcast, mrtrix, fsl or dipy.
    pub tensor_order: Option<String>,
    /// `AXIS[:INDEX]`.
    pub slice: Option<String>,
    /// I,J,K or mid.
    pub slices: Option<String>,
    /// Every voxel of `voxels` (the whole volume without it) in 3D, instead of a slice.
    pub block: bool,
    /// i0:i1,j0:j1,k0:k1.
    pub voxels: Option<String>,
    /// Glyphs only where the mask is nonzero.
    pub mask: Option<ImageSource<Mask>>,
    /// World radius of the largest glyph.
    pub scale: Option<f64>,
    /// sqrt, robust, global, per-glyph or none.
    pub norm: Option<String>,
    /// Leave out glyphs below this largest radius.
    pub min_amplitude: Option<f64>,
    /// A perspective camera.
    pub perspective: bool,
    /// radiological or neurological.
    pub orientation: Option<String>,
    /// polynomial or ellipsoid.
    pub glyph: Option<String>,
    /// An anatomical image drawn on the slice planes (of every panel of a montage).
    pub underlay: Option<ImageSource<UnderlayVolume>>,
    /// LOW:HIGH, the underlay's window.
    pub underlay_range: Option<String>,
    /// back or centre: where the underlay's plane lies.
    pub underlay_plane: Option<String>,
    /// A montage of views: axial, coronal and sagittal (each optionally :INDEX), comma
    /// separated.
    pub views: Option<String>,
    /// A montage of this many evenly spaced slices of the slice plane.
    pub lightbox: Option<usize>,
    /// Fibre peaks drawn in the slices' voxels: a peak image (see `volume::peaks` for
    /// the layouts), or one in memory.
    pub peaks: Option<ImageSource<PeakVolume>>,
    /// The amplitudes of DIPY's unit peak directions: names the DIPY layout (files only).
    pub peak_values: Option<PathBuf>,
    /// direction, or one colour (a name, #rrggbb or r,g,b).
    pub peaks_color: Option<String>,
    /// global, unit or none.
    pub peaks_norm: Option<String>,
    /// World half length of the longest peak.
    pub peaks_scale: Option<f64>,
    /// Peak diameter in pixels.
    pub peaks_width: Option<f64>,
    /// voxel or world: the axes of the peaks' directions (default: the file's own).
    pub peaks_frame: Option<String>,
    /// Streamlines drawn as tubes with the glyphs: a tractogram file (.tck, .trk, .trx)
    /// or one in memory.
    pub tracks: Option<ImageSource<Tractogram>>,
    /// direction, or one colour (a name, #rrggbb or r,g,b).
    pub tracks_color: Option<String>,
    /// The tubes' radius, millimetres.
    pub tracks_radius: Option<f64>,
    /// tubes (the default) or lines.
    pub tracks_style: Option<String>,
    /// The most streamlines drawn: a uniform subsample of them.
    pub tracks_max: Option<usize>,
    /// On slice views, only the parts of streamlines within this many millimetres of a
    /// slice's plane.
    pub slab: Option<f64>,
}

impl VolumeRequest {
    /// Checks that the options fit `input` and each other, before anything is read.
    pub fn check(&self, input: Coefficients) -> Result<()> {
        self.check_block()?;
        self.underlay_range()?;
        self.underlay_placement()?;
        self.check_input(input)?;
        self.check_montage()?;
        if self.slice.is_some() && self.slices.is_some() {
            return Err(Error::conflict(
                Setting::Slice,
                glyphcast::error::Relation::Exclusive,
                Setting::Slices,
            ));
        }
        self.frame()?;
        self.peaks_frame()?;
        self.given_basis()?;
        self.peak_style()?;
        self.track_style()?;
        Ok(())
    }

    /// How the tracks are drawn; their options need the tracks.
    pub fn track_style(&self) -> Result<TrackStyle> {
        let given = [
            (DmriSetting::TracksColor, self.tracks_color.is_some()),
            (DmriSetting::TracksRadius, self.tracks_radius.is_some()),
            (DmriSetting::TracksStyle, self.tracks_style.is_some()),
            (DmriSetting::TracksMax, self.tracks_max.is_some()),
            (DmriSetting::Slab, self.slab.is_some()),
        ];
        if self.tracks.is_none()
            && let Some((setting, _)) = given.iter().find(|(_, on)| *on)
        {
            return Err(Error::setting(
                *setting,
                glyphcast::message!["needs ", DmriSetting::Tracks, " (the tracks it applies to)"],
            ));
        }
        let style = TrackStyle {
            radius: self.tracks_radius.unwrap_or(DEFAULT_TRACKS_RADIUS_MM),
            shape: self
                .tracks_style
                .as_deref()
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            // A scalar colour is resolved against the tractogram (`read_tracks`).
            color: self
                .tracks_color
                .as_deref()
                .filter(|text| scalar_request(text).is_none())
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            slab: self.slab,
        };
        style.validate()?;
        Ok(style)
    }

    /// The tracks asked for, read if they are a file and subsampled to `tracks_max`,
    /// with their style.
    pub fn read_tracks(&self) -> Result<Option<ViewTracks>> {
        let mut style = self.track_style()?;
        let (tractogram, file) = match &self.tracks {
            None => return Ok(None),
            Some(ImageSource::File(path)) => (read_tractogram(path)?, path.display().to_string()),
            Some(ImageSource::Memory(tractogram)) => (tractogram.clone(), "tracks".to_owned()),
        };
        // A value's range is the whole file's, whatever --tracks-max keeps (subsampling
        // keeps the values' order).
        if let Some(name) = self.tracks_color.as_deref().and_then(scalar_request) {
            style.color = TracksColor::Scalar(ScalarColor::of(&tractogram, name, &file)?);
        }
        let tractogram = match self.tracks_max {
            Some(max) if max < tractogram.len() => subsample(&tractogram, max),
            _ => tractogram,
        };
        Ok(Some(ViewTracks {
            tractogram: Arc::new(tractogram),
            style,
        }))
    }

    /// How the peaks are drawn; the style options need the peaks, values need a file.
    pub fn peak_style(&self) -> Result<PeakStyle> {
        let given = [
            (Setting::PeakValues, self.peak_values.is_some()),
            (Setting::PeaksColor, self.peaks_color.is_some()),
            (Setting::PeaksNorm, self.peaks_norm.is_some()),
            (Setting::PeaksScale, self.peaks_scale.is_some()),
            (Setting::PeaksWidth, self.peaks_width.is_some()),
            (Setting::PeaksFrame, self.peaks_frame.is_some()),
        ];
        if self.peaks.is_none()
            && let Some((setting, _)) = given.iter().find(|(_, on)| *on)
        {
            return Err(Error::setting(
                *setting,
                glyphcast::message!["needs ", Setting::Peaks, " (the peaks it applies to)"],
            ));
        }
        if matches!(self.peaks, Some(ImageSource::Memory(_))) && self.peak_values.is_some() {
            return Err(Error::setting(
                Setting::PeakValues,
                glyphcast::message![
                    "goes with a peak file; peaks in memory carry their amplitudes (",
                    Setting::Peaks,
                    ")"
                ],
            ));
        }
        let color = self
            .peaks_color
            .as_deref()
            .map(str::parse)
            .transpose()?
            .unwrap_or_default();
        let style = PeakStyle {
            color,
            norm: self
                .peaks_norm
                .as_deref()
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            scale: self.peaks_scale,
            width: self.peaks_width.unwrap_or(DEFAULT_PEAKS_WIDTH),
        };
        style.validate()?;
        Ok(style)
    }

    /// The peaks asked for, read if they are a file, with their style.
    pub fn read_peaks(&self) -> Result<Option<ViewPeaks>> {
        let style = self.peak_style()?;
        let volume = match &self.peaks {
            None => return Ok(None),
            Some(ImageSource::File(path)) => {
                load_peaks(path, self.peak_values.as_deref(), self.peaks_frame()?)?
            }
            Some(ImageSource::Memory(peaks)) => peaks.clone(),
        };
        Ok(Some(ViewPeaks {
            volume: Arc::new(volume),
            style,
        }))
    }

    /// The stand-in volume of a view of the peaks alone: their grid, no glyphs
    /// ([`Volume::grid_of_peaks`]); the options that belong to glyphs are refused.
    pub fn peaks_grid(&self) -> Result<Volume> {
        let glyph_only = [
            (Setting::Basis, self.basis.is_some()),
            (Setting::ForceBasis, self.force_basis),
            (Setting::Legacy, self.legacy.is_some()),
            (Setting::Lmax, self.lmax.is_some()),
            (Setting::Order, self.order.is_some()),
            (Setting::Nonsymmetric, self.nonsymmetric),
            (Setting::Frame, self.frame.is_some()),
            (Setting::Glyph, self.glyph.is_some()),
            (Setting::Scale, self.scale.is_some()),
            (Setting::Norm, self.norm.is_some()),
            (Setting::MinAmplitude, self.min_amplitude.is_some()),
        ];
        if let Some((setting, _)) = glyph_only.iter().find(|(_, on)| *on) {
            return Err(Error::setting(
                *setting,
                "applies to glyphs, and only peaks are drawn",
            ));
        }
        self.underlay_range()?;
        self.check_montage()?;
        let peaks = self.read_peaks()?.ok_or_else(|| {
            Error::setting(Setting::Peaks, "a view of peaks alone needs the peaks")
        })?;
        Volume::grid_of_peaks(&peaks.volume)
    }

    /// The options that belong to the other kind of coefficients are refused, and a
    /// tensor volume needs its order.
    fn check_input(&self, input: Coefficients) -> Result<()> {
        let misplaced = |setting: Setting, kind: &str| {
            Err(Error::setting(
                setting,
                format!("applies to {kind} volumes only"),
            ))
        };
        match input {
            Coefficients::Sh => {
                if self.order.is_some() {
                    return misplaced(Setting::Order, "tensor");
                }
                if self.nonsymmetric {
                    return misplaced(Setting::Nonsymmetric, "tensor");
                }
                if self.tensor_order.is_some() {
                    return misplaced(Setting::TensorOrder, "tensor");
                }
            }
            Coefficients::Tensor => {
                for (setting, given) in [
                    (Setting::Basis, self.basis.is_some()),
                    (Setting::ForceBasis, self.force_basis),
                    (Setting::Legacy, self.legacy.is_some()),
                    (Setting::Lmax, self.lmax.is_some()),
                ] {
                    if given {
                        return misplaced(setting, "SH");
                    }
                }
                let order = self.tensor_order()?;
                if let Some(stored) = self.given_tensor_order()? {
                    stored.check_applies(order, !self.nonsymmetric)?;
                }
            }
        }
        Ok(())
    }

    /// The stored order of a tensor volume's entries, if given.
    pub fn given_tensor_order(&self) -> Result<Option<TensorOrder>> {
        self.tensor_order.as_deref().map(str::parse).transpose()
    }

    /// Everything about the view but the mask, which [`VolumeRequest::figure`] reads.
    pub fn options(&self, image: ImageRequest) -> Result<VolumeOptions> {
        Ok(VolumeOptions {
            slices: self.slices.as_deref().map(str::parse).transpose()?,
            slice: parse_or_default(self.slice.as_deref())?,
            block: self.block,
            voxels: parse_or_default(self.voxels.as_deref())?,
            mask: None,
            shape: self.shape()?.unwrap_or_default(),
            scale: self.scale,
            norm: parse_or_default(self.norm.as_deref())?,
            min_amplitude: self.min_amplitude.unwrap_or(0.0),
            lmax: self.lmax,
            projection: if self.perspective {
                ViewProjection::Perspective
            } else {
                ViewProjection::Orthographic
            },
            orientation: parse_or_default(self.orientation.as_deref())?,
            // A lightbox captions each panel with its slice in the top-left corner: the
            // panels keep the edge band free of glyphs, as edge labels do.
            image: ImageRequest {
                keep_edges: image.keep_edges || self.lightbox.is_some(),
                ..image
            },
            peaks: None,
            tracks: None,
        })
    }

    /// The glyph shape, if given.
    pub fn shape(&self) -> Result<Option<GlyphShape>> {
        self.glyph.as_deref().map(str::parse).transpose()
    }

    /// The coefficients' frame, if given.
    pub fn frame(&self) -> Result<Option<CoefficientFrame>> {
        parse_frame(self.frame.as_deref(), Setting::Frame)
    }

    /// The frame of the peaks' directions, if given.
    pub fn peaks_frame(&self) -> Result<Option<CoefficientFrame>> {
        parse_frame(self.peaks_frame.as_deref(), Setting::PeaksFrame)
    }

    /// The basis with its legacy choice (aliases name both; see `glyph::sh::parse_basis_choice`), if
    /// given.
    pub fn given_basis(&self) -> Result<Option<(ShBasis, bool)>> {
        match self.basis.as_deref() {
            Some(name) => parse_basis_choice(name, self.legacy).map(Some),
            None if self.legacy.is_some() => Err(Error::setting(
                Setting::Legacy,
                glyphcast::message![
                    "needs ",
                    Setting::Basis,
                    " too (it picks the legacy variant of the basis)"
                ],
            )),
            None if self.force_basis => Err(Error::setting(
                Setting::ForceBasis,
                glyphcast::message!["needs ", Setting::Basis, " (the basis to force)"],
            )),
            None => Ok(None),
        }
    }

    /// The underlay's window, if given: LOW:HIGH, finite, LOW < HIGH; it needs an
    /// underlay.
    pub fn underlay_range(&self) -> Result<Option<(f64, f64)>> {
        let Some(text) = self.underlay_range.as_deref() else {
            return Ok(None);
        };
        if self.underlay.is_none() {
            return Err(Error::setting(
                Setting::UnderlayRange,
                glyphcast::message!["needs ", Setting::Underlay, " (the image it windows)"],
            ));
        }
        let parsed = text.split_once(':').and_then(|(lo, hi)| {
            Some((
                lo.trim().parse::<f64>().ok()?,
                hi.trim().parse::<f64>().ok()?,
            ))
        });
        match parsed {
            Some((lo, hi)) if lo.is_finite() && hi.is_finite() && lo < hi => Ok(Some((lo, hi))),
            _ => Err(Error::setting_value(
                Setting::UnderlayRange,
                format!("'{}'", quoted(text)),
                "not LOW:HIGH with finite numbers, LOW < HIGH",
            )),
        }
    }

    /// Where the underlay's plane lies (default: behind the glyphs); it needs an
    /// underlay.
    pub fn underlay_placement(&self) -> Result<UnderlayPlacement> {
        let Some(text) = self.underlay_plane.as_deref() else {
            return Ok(UnderlayPlacement::default());
        };
        if self.underlay.is_none() {
            return Err(Error::setting(
                Setting::UnderlayPlane,
                glyphcast::message!["needs ", Setting::Underlay, " (the image it places)"],
            ));
        }
        text.parse()
    }

    /// A note when MRtrix's basis is named for a NIfTI file with no frame given: its
    /// coefficients are then read in voxel axes (the NIfTI default), while a NIfTI that
    /// MRtrix's `mrconvert` wrote keeps them in scanner axes.
    fn frame_note(&self, file: &Image) -> Option<glyphcast::error::Message> {
        let named_mrtrix = self
            .basis
            .as_deref()
            .is_some_and(|name| name.trim().eq_ignore_ascii_case("mrtrix"));
        let nifti = matches!(file.header, ImageHeader::Nifti(_));
        if !(named_mrtrix && nifti && self.frame.is_none()) {
            return None;
        }
        Some(glyphcast::message![
            format!("{}: with ", file.file),
            Setting::Basis.with("mrtrix"),
            " the coefficients of this NIfTI are read in its voxel axes (the NIfTI default); \
             a NIfTI written by MRtrix's mrconvert keeps scanner axes: give ",
            Setting::Frame.with("world"),
            " for such a file, or ",
            Setting::Frame.with("voxel"),
            " to keep this reading without the note"
        ])
    }

    /// The kind of the coefficients: for SH the basis given and what `file` records
    /// ([`resolve_basis`]; coefficients from memory, with no file, need the basis), for
    /// tensors the layout of the order and symmetry given.
    pub fn kind(&self, input: Coefficients, file: Option<&Image>) -> Result<VolumeKind> {
        match input {
            Coefficients::Sh => {
                let given = self.given_basis()?;
                let (basis, legacy) = match file {
                    Some(file) => resolve_basis(file, given, self.force_basis)?,
                    None => given.ok_or_else(|| {
                        Error::setting(
                            Setting::Basis,
                            "SH coefficients without a file need their basis: tournier07, \
                             descoteaux07, mrtrix, dipy or dipy-new",
                        )
                    })?,
                };
                Ok(VolumeKind::Sh { basis, legacy })
            }
            Coefficients::Tensor => {
                let order = self.tensor_order()?;
                let symmetry = if self.nonsymmetric {
                    Symmetry::NonSymmetric
                } else {
                    Symmetry::Symmetric
                };
                Ok(VolumeKind::Tensor(TensorLayout { order, symmetry }))
            }
        }
    }

    /// The tensor order, which a tensor volume needs.
    pub fn tensor_order(&self) -> Result<u32> {
        self.order.ok_or_else(|| {
            Error::setting(
                Setting::Order,
                glyphcast::message![
                    "a tensor volume needs ",
                    Setting::Order.with("N"),
                    " (the tensor order of its coefficients)"
                ],
            )
        })
    }

    /// Reads the volume of `input` from `path`, after [`VolumeRequest::check`]: its kind
    /// from the options and the file ([`VolumeRequest::kind`]), in the frame asked for.
    pub fn read_volume(&self, input: Coefficients, path: &Path) -> Result<Volume> {
        self.check(input)?;
        self.options(ImageRequest::default())?;
        let file = read_image(path)?;
        // The shape before the basis: a 3D file is not 4D, whatever it records.
        check_four_d(&file)?;
        check_content(
            &file,
            match input {
                Coefficients::Sh => RecordedContent::Sh,
                Coefficients::Tensor => RecordedContent::Tensor(self.order.unwrap_or(0)),
            },
        )?;
        let note = match input {
            Coefficients::Sh => tensor_hint(&file)?,
            Coefficients::Tensor => None,
        };
        if input == Coefficients::Sh {
            check_variant_named(
                self.basis.as_deref(),
                self.legacy,
                self.force_basis,
                Some(&file),
                &file.file,
            )?;
        }
        let kind = self.kind(input, Some(&file))?;
        self.check_shape(kind, &file.file)?;
        let stored = self.stored_order(kind, Some(&file))?;
        let frame_note = self.frame_note(&file);
        let mut volume = Volume::from_image(file, kind)?;
        volume.notes.extend(note);
        volume.notes.extend(frame_note);
        let volume = in_glyphcast_order(volume, stored)?;
        self.in_frame(volume, stored)
    }

    /// The volume of `input` held in memory: `data` of shape [x, y, z, coefficients]
    /// placed by `voxel_to_world` (`name` names it in messages), after
    /// [`VolumeRequest::check`], in the frame asked for (voxel by default).
    pub fn memory_volume(
        &self,
        input: Coefficients,
        name: &str,
        data: ndarray::Array4<f64>,
        voxel_to_world: VoxelToWorld,
    ) -> Result<Volume> {
        self.check(input)?;
        self.options(ImageRequest::default())?;
        if input == Coefficients::Sh {
            check_variant_named(
                self.basis.as_deref(),
                self.legacy,
                self.force_basis,
                None,
                name,
            )?;
        }
        let kind = self.kind(input, None)?;
        self.check_shape(kind, name)?;
        let stored = self.stored_order(kind, None)?;
        let volume = Volume::new(name, data, kind, voxel_to_world)?;
        let volume = in_glyphcast_order(volume, stored)?;
        self.in_frame(volume, stored)
    }

    /// The stored order of a tensor volume's entries and where it comes from
    /// ([`resolve_tensor_order`]); `None` for SH.
    fn stored_order(
        &self,
        kind: VolumeKind,
        file: Option<&Image>,
    ) -> Result<Option<(TensorOrder, OrderSource)>> {
        match kind {
            VolumeKind::Sh { .. } => Ok(None),
            VolumeKind::Tensor(layout) => {
                resolve_tensor_order(file, self.given_tensor_order()?, layout).map(Some)
            }
        }
    }

    /// The ellipsoid needs an order-2 symmetric tensor volume.
    fn check_shape(&self, kind: VolumeKind, name: &str) -> Result<()> {
        if self.shape()? == Some(GlyphShape::Ellipsoid)
            && kind != VolumeKind::Tensor(ELLIPSOID_LAYOUT)
        {
            return Err(Error::setting_value(
                Setting::Glyph,
                "ellipsoid",
                glyphcast::message![
                    "draws order-2 symmetric tensors (DTI: a tensor volume with ",
                    Setting::Order.with(2),
                    format!("), not {name}")
                ],
            ));
        }
        Ok(())
    }

    /// `volume` in the frame asked for, if any. FSL's tensors are in FSL's frame, made of
    /// the voxel axes (`TensorOrder::negates_x`): scanner axes do not go with them.
    fn in_frame(
        &self,
        mut volume: Volume,
        stored: Option<(TensorOrder, OrderSource)>,
    ) -> Result<Volume> {
        let frame = self.frame()?;
        if let (Some(CoefficientFrame::World), Some((TensorOrder::Fsl, _))) = (frame, stored) {
            return Err(Error::conflict(
                Setting::Frame.with("world"),
                glyphcast::error::Relation::Excludes,
                Setting::TensorOrder.with("fsl"),
            ));
        }
        volume.frame = frame.unwrap_or(volume.frame);
        Ok(volume)
    }

    /// A block is a view of its own: no slice, three slices or montage, and no underlay
    /// (which lies on slice planes, and a block has none).
    fn check_block(&self) -> Result<()> {
        if !self.block {
            return Ok(());
        }
        let views = [
            (Setting::Slice, self.slice.is_some()),
            (Setting::Slices, self.slices.is_some()),
            (Setting::Views, self.views.is_some()),
            (Setting::Lightbox, self.lightbox.is_some()),
        ];
        if let Some((setting, _)) = views.iter().find(|(_, given)| *given) {
            return Err(Error::conflict(
                Setting::Block,
                glyphcast::error::Relation::Exclusive,
                *setting,
            ));
        }
        if self.underlay.is_some() {
            return Err(Error::conflict(
                Setting::Block,
                glyphcast::error::Relation::Excludes,
                Setting::Underlay,
            ));
        }
        Ok(())
    }

    /// Whether a montage (views or a lightbox) is asked for.
    pub fn is_montage(&self) -> bool {
        self.views.is_some() || self.lightbox.is_some()
    }

    /// The montage options on their own: one of views and lightbox, a lightbox count in
    /// 1 to [`MAX_PANELS`] along the slice plane, the slices left to views.
    pub(super) fn check_montage(&self) -> Result<()> {
        if !self.is_montage() {
            return Ok(());
        }
        match (&self.views, self.lightbox) {
            (Some(_), Some(_)) => {
                return Err(Error::conflict(
                    Setting::Views,
                    glyphcast::error::Relation::Exclusive,
                    Setting::Lightbox,
                ));
            }
            (Some(views), None) => {
                parse_views(views)?;
            }
            (None, count) => {
                let count = count.unwrap_or_default();
                if self.slices.is_some() {
                    return Err(Error::setting(
                        Setting::Lightbox,
                        glyphcast::message!["takes ", Setting::Slice, ", not ", Setting::Slices],
                    ));
                }
                if count == 0 || count > MAX_PANELS {
                    return Err(Error::setting_value(
                        Setting::Lightbox,
                        count,
                        format!("must be 1 to {MAX_PANELS} slices"),
                    ));
                }
            }
        }
        if self.slices.is_some() || (self.views.is_some() && self.slice.is_some()) {
            return Err(Error::setting(
                Setting::Views,
                glyphcast::message![
                    "names each panel's slice: give no ",
                    Setting::Slice,
                    " or ",
                    Setting::Slices,
                    " with it"
                ],
            ));
        }
        Ok(())
    }
}

/// For six coefficients per voxel read as SH (band 2): an error when the file records a
/// tensor fit (glyphcast's own record), a note when its header (NIfTI's symmetric-matrix
/// intent) or its name (dt, dti, tensor) suggests a DTI tensor.
fn tensor_hint(file: &Image) -> Result<Option<glyphcast::error::Message>> {
    if file.shape(4).get(3) != Some(&6) {
        return Ok(None);
    }
    // A file glyphcast recorded as a tensor is refused before (`check_content`).
    const NIFTI_INTENT_SYMMATRIX: i32 = 1005;
    let intent =
        matches!(&file.header, ImageHeader::Nifti(h) if h.intent_code == NIFTI_INTENT_SYMMATRIX);
    let name = std::path::Path::new(&file.file)
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let named = name
        .split(|c: char| !c.is_ascii_alphanumeric())
        .any(|word| matches!(word, "dt" | "dti" | "tensor" | "tensors" | "dtifit"))
        || name.contains("tensor")
        || name.contains("lower_triangular");
    let why = match (intent, named) {
        (true, _) => "its header's intent is a symmetric matrix",
        (false, true) => "its name suggests a diffusion tensor",
        (false, false) => return Ok(None),
    };
    Ok(Some(glyphcast::message![
        format!(
            "{}: 6 coefficients per voxel, drawn as SH of band 2, but {why}: if it holds \
         tensors, render or view draw it as a tensor volume (with ",
            file.file
        ),
        Setting::Order.with(2),
        ", and ",
        Setting::TensorOrder,
        " naming the order of its entries); qc and peaks read SH coefficients only"
    ]))
}

/// `volume`'s DTI entries put in glyphcast's order from `stored`; an order only assumed
/// (neither given nor recorded) is refused when the values contradict it
/// ([`OrderEvidence::contradicts`]), rather than drawn as indefinite tensors.
fn in_glyphcast_order(
    mut volume: Volume,
    stored: Option<(TensorOrder, OrderSource)>,
) -> Result<Volume> {
    let Some((stored, source)) = stored else {
        return Ok(volume);
    };
    let GlyphKind::Tensor(layout) = volume.kind else {
        return Ok(volume);
    };
    if !has_dti_entries(layout) {
        return Ok(volume);
    }
    if source == OrderSource::Assumed {
        let evidence = volume.order_evidence();
        if let Some(other) = evidence.contradicts(stored) {
            return Err(Error::input(
                &volume.file,
                "values",
                glyphcast::message![
                    format!(
                        "{} of {} tensors are not positive definite read in {}'s order \
                     ({}), {} in {}'s ({}): the entries are not in {}'s order, and \
                     nothing records theirs; give ",
                        evidence.not_positive_in(stored),
                        evidence.tensors,
                        stored.owner(),
                        stored.entries(),
                        evidence.not_positive_in(other),
                        other.owner(),
                        other.entries(),
                        stored.owner()
                    ),
                    Setting::TensorOrder.with(other),
                    " (or ",
                    Setting::TensorOrder.with(stored),
                    " to draw them as they are read \
                     now)"
                ],
            ));
        }
    }
    volume.reorder_tensors(stored);
    Ok(volume)
}

/// A frame setting's value (voxel or world), if given.
fn parse_frame(text: Option<&str>, setting: Setting) -> Result<Option<CoefficientFrame>> {
    text.map(|text| {
        text.parse()
            .map_err(|err: Error| Error::setting(setting, err.to_string()))
    })
    .transpose()
}

fn parse_or_default<T>(text: Option<&str>) -> Result<T>
where
    T: std::str::FromStr<Err = Error> + Default,
{
    Ok(text.map(str::parse).transpose()?.unwrap_or_default())
}

/// The views of a montage: axial, coronal and sagittal (each optionally :INDEX), comma
/// separated, each at most once.
pub fn parse_views(text: &str) -> Result<Vec<Slice>> {
    let shown = || format!("'{}'", quoted(text));
    let mut slices: Vec<Slice> = Vec::new();
    for item in text.split(',') {
        let slice: Slice = item.trim().parse().map_err(|_| {
            Error::setting_value(
                Setting::Views,
                shown(),
                format!(
                    "'{}' is not axial, coronal or sagittal (optionally :INDEX)",
                    quoted(item)
                ),
            )
        })?;
        if slices.iter().any(|s| s.axis == slice.axis) {
            return Err(Error::setting_value(
                Setting::Views,
                shown(),
                format!("{} is listed twice", slice.axis.name()),
            ));
        }
        slices.push(slice);
    }
    Ok(slices)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every refusal names its setting (or the settings that clash), never a front end's
    /// spelling of it.
    #[test]
    fn refusals_name_the_setting_and_no_flag() {
        let base = VolumeRequest {
            order: Some(2),
            ..Default::default()
        };
        let cases: Vec<(VolumeRequest, Coefficients, Option<Setting>)> = vec![
            (base.clone(), Coefficients::Sh, Some(Setting::Order)),
            (
                Default::default(),
                Coefficients::Tensor,
                Some(Setting::Order),
            ),
            (
                VolumeRequest {
                    lmax: Some(4),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Lmax),
            ),
            (
                VolumeRequest {
                    legacy: Some(true),
                    ..Default::default()
                },
                Coefficients::Sh,
                Some(Setting::Legacy),
            ),
            (
                VolumeRequest {
                    basis: Some("fsl".into()),
                    ..Default::default()
                },
                Coefficients::Sh,
                Some(Setting::Basis),
            ),
            (
                VolumeRequest {
                    frame: Some("scanner".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Frame),
            ),
            (
                VolumeRequest {
                    underlay_range: Some("0:1".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::UnderlayRange),
            ),
            (
                VolumeRequest {
                    underlay: Some(ImageSource::File("fa.nii".into())),
                    underlay_range: Some("1:0".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::UnderlayRange),
            ),
            (
                VolumeRequest {
                    lightbox: Some(0),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Lightbox),
            ),
            (
                VolumeRequest {
                    lightbox: Some(4),
                    slices: Some("mid".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Lightbox),
            ),
            (
                VolumeRequest {
                    views: Some("axial,axial".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Views),
            ),
            (
                VolumeRequest {
                    views: Some("axial".into()),
                    slice: Some("coronal".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Views),
            ),
            (
                VolumeRequest {
                    underlay_plane: Some("centre".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::UnderlayPlane),
            ),
            (
                VolumeRequest {
                    views: Some("axial".into()),
                    lightbox: Some(2),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Views),
            ),
            (
                VolumeRequest {
                    slice: Some("axial".into()),
                    slices: Some("mid".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Slice),
            ),
            (
                VolumeRequest {
                    block: true,
                    slices: Some("mid".into()),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Block),
            ),
            (
                VolumeRequest {
                    block: true,
                    lightbox: Some(4),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Block),
            ),
            (
                VolumeRequest {
                    block: true,
                    underlay: Some(ImageSource::File("fa.nii".into())),
                    ..base.clone()
                },
                Coefficients::Tensor,
                Some(Setting::Block),
            ),
        ];
        for (request, input, setting) in cases {
            let err = request.check(input).expect_err("refused");
            assert_eq!(err.setting_of(), setting, "{err}");
            let text = err.to_string();
            assert!(!text.contains("--"), "{text}");
            assert!(err.is_usage(), "{text}");
            match (&err, setting) {
                // Options that clash name both sides.
                (Error::Conflict { .. }, Some(setting)) => {
                    assert!(text.contains(setting.name()), "{text}")
                }
                (_, Some(setting)) => assert!(text.starts_with(setting.name()), "{text}"),
                (_, None) => {}
            }
        }
        // Values the options cannot parse.
        for (request, setting) in [
            (
                VolumeRequest {
                    glyph: Some("cuboid".into()),
                    ..Default::default()
                },
                Setting::Glyph,
            ),
            (
                VolumeRequest {
                    norm: Some("loud".into()),
                    ..Default::default()
                },
                Setting::Norm,
            ),
            (
                VolumeRequest {
                    orientation: Some("upside-down".into()),
                    ..Default::default()
                },
                Setting::Orientation,
            ),
            (
                VolumeRequest {
                    slice: Some("diagonal".into()),
                    ..Default::default()
                },
                Setting::Slice,
            ),
        ] {
            let err = request
                .options(ImageRequest::default())
                .expect_err("refused");
            assert_eq!(err.setting_of(), Some(setting), "{err}");
            assert!(!err.to_string().contains("--"), "{err}");
        }
    }

    #[test]
    fn an_ellipsoid_needs_an_order_2_tensor_volume() {
        let request = VolumeRequest {
            order: Some(4),
            glyph: Some("ellipsoid".into()),
            ..Default::default()
        };
        let data = ndarray::Array4::zeros((1, 1, 1, 15));
        let map = VoxelToWorld::new(
            glam::DMat4::IDENTITY,
            crate::io::nifti::AffineSource::Sform,
            "v",
            "affine",
        )
        .expect("identity");
        let err = request
            .memory_volume(Coefficients::Tensor, "v", data, map)
            .expect_err("order 4");
        assert_eq!(err.setting_of(), Some(Setting::Glyph));
        assert_eq!(
            err.to_string(),
            "glyph ellipsoid: draws order-2 symmetric tensors (DTI: a tensor volume with \
             order 2), not v"
        );
    }
}
