//! The figure a [`VolumeRequest`] asks of a volume: one view (a slice, or three
//! orthogonal ones) with its underlay, or a montage of panels, one per view
//! ([`Setting::Views`]) or per evenly spaced slice ([`Setting::Lightbox`]), each panel the
//! scene the single view of its slice would be. Both front ends draw what this gives.
use std::sync::Arc;

use super::build::{VolumeOptions, VolumeScene, is_nothing_to_draw, volume_scene};
use super::framing::ImageRequest;
use super::input::{Mask, Volume, load_mask};
use super::request::{ImageSource, VolumeRequest, parse_views};
use super::selection::Slice;
use super::underlay::{load_underlay, view_underlay};
use crate::io::nifti::AffineSource;
use glyphcast::render::underlay::{Underlay, UnderlayVolume};
use glyphcast::{Error, Result, Setting};

/// What a request makes of a volume.
pub enum VolumeFigure {
    /// One view.
    View(Box<VolumeView>),
    /// Several panels in one image.
    Montage(VolumeMontage),
}

/// A volume's view: the scene, what it was made from and its underlay.
pub struct VolumeView {
    /// The volume, in the frame asked for.
    pub volume: Volume,
    /// The options the view was made with (the slice in voxel axes, the mask read).
    pub options: VolumeOptions,
    /// The scene and its report.
    pub scene: VolumeScene,
    /// The underlay on the view's slice planes, if one was asked for.
    pub underlay: Option<Underlay>,
    /// Notes for the user (the world plane asked for is another voxel axis; a basis
    /// name read as another front end reads it).
    pub notes: Vec<glyphcast::error::Message>,
    /// Warnings for the user ([`super::VolumeReport::warnings`]).
    pub warnings: Vec<glyphcast::error::Message>,
}

/// The panels of a montage before their scenes are built
/// ([`VolumeRequest::montage_plan`]).
pub struct MontagePlan {
    /// Each panel's options, its slice in voxel axes, in reading order.
    pub panels: Vec<VolumeOptions>,
    /// Panels to a row: all of them for views, ceil(sqrt(N)) for a lightbox of N.
    pub columns: usize,
    /// Notes for the user (a world plane that is another voxel axis), each once.
    pub notes: Vec<glyphcast::error::Message>,
}

/// The panels of a montage.
pub struct VolumeMontage {
    /// The volume's name in messages (its file).
    pub file: String,
    /// Each panel's scene and report, in reading order (left to right, then down).
    pub panels: Vec<VolumeScene>,
    /// Each panel's underlay on its slice plane, if one was asked for.
    pub underlays: Vec<Option<Underlay>>,
    /// Each panel's caption: the slice it shows ("k=12"), for a lightbox.
    pub captions: Vec<Option<String>>,
    /// Panels to a row: all of them for views, ceil(sqrt(N)) for a lightbox of N.
    pub columns: usize,
    /// Notes for the user (a world plane that is another voxel axis), each once.
    pub notes: Vec<glyphcast::error::Message>,
    /// Warnings for the user, for all panels together
    /// ([`super::VolumeReport::warnings`]).
    pub warnings: Vec<glyphcast::error::Message>,
}

impl VolumeFigure {
    /// The figure's notes and warnings.
    pub fn messages(&self) -> (&[glyphcast::error::Message], &[glyphcast::error::Message]) {
        match self {
            VolumeFigure::View(view) => (&view.notes, &view.warnings),
            VolumeFigure::Montage(montage) => (&montage.notes, &montage.warnings),
        }
    }
}

/// What the colours of streamlines coloured by a per-point value mean: the value's name
/// and the range viridis spans.
fn scalar_note(tracks: &crate::volume::ViewTracks) -> Option<glyphcast::error::Message> {
    let crate::volume::TracksColor::Scalar(scalar) = tracks.style.color else {
        return None;
    };
    let name = &tracks.tractogram.point_values.get(scalar.index)?.name;
    // Four significant digits, as a reader compares them.
    let show = |v: f64| {
        let digits = 3 - v.abs().max(1e-300).log10().floor() as i32;
        format!("{v:.*}", digits.clamp(0, 9) as usize)
    };
    Some(glyphcast::message![format!(
        "streamlines coloured by {name}: viridis from {} (dark blue) to {} (yellow)",
        show(scalar.low),
        show(scalar.high)
    )])
}

impl VolumeRequest {
    /// The figure of `volume` (from [`VolumeRequest::read_volume`] or
    /// [`VolumeRequest::memory_volume`]) at the image size `image`: a montage when views
    /// or a lightbox are asked for, else one view with its underlay.
    pub fn figure(&self, volume: Volume, image: ImageRequest) -> Result<VolumeFigure> {
        self.check_montage()?;
        let mut options = self.options(image)?;
        options.mask = self.read_mask()?;
        options.peaks = self.read_peaks()?;
        options.tracks = self.read_tracks()?;
        let note = options.tracks.as_ref().and_then(scalar_note);
        let mut figure = if self.is_montage() {
            self.montage(&volume, &options).map(VolumeFigure::Montage)?
        } else {
            self.view(volume, options)
                .map(|view| VolumeFigure::View(Box::new(view)))?
        };
        if let Some(note) = note {
            match &mut figure {
                VolumeFigure::View(view) => view.notes.push(note),
                VolumeFigure::Montage(montage) => montage.notes.push(note),
            }
        }
        Ok(figure)
    }

    /// The view of `volume` with `options` (from [`VolumeRequest::options`], with a
    /// mask if any): the slice's world plane turned into the voxel axis closest to it,
    /// the scene, and the underlay on its planes.
    pub fn view(&self, volume: Volume, mut options: VolumeOptions) -> Result<VolumeView> {
        let mut notes = volume.notes.clone();
        notes.extend(slice_in_voxels(&mut options, &volume)?.map(Into::into));
        let scene = volume_scene(&volume, &options)?;
        let underlay = self.underlay(&volume, &scene)?;
        let warnings = scene.report.warnings(&volume.file);
        Ok(VolumeView {
            volume,
            options,
            scene,
            underlay,
            notes,
            warnings,
        })
    }

    /// The mask asked for, read if it is a file.
    fn read_mask(&self) -> Result<Option<Mask>> {
        match &self.mask {
            None => Ok(None),
            Some(ImageSource::File(path)) => load_mask(path).map(Some),
            Some(ImageSource::Memory(mask)) => Ok(Some(mask.clone())),
        }
    }

    /// The underlay asked for, read once and windowed (the underlay range, else the 2nd
    /// to 98th percentile), with the source of its affine.
    fn underlay_volume(&self) -> Result<Option<(Arc<UnderlayVolume>, AffineSource)>> {
        let range = self.underlay_range()?;
        let (mut underlay, source) = match &self.underlay {
            None => return Ok(None),
            Some(ImageSource::File(path)) => load_underlay(path)?,
            Some(ImageSource::Memory(underlay)) => (underlay.clone(), AffineSource::Sform),
        };
        if let Some((lo, hi)) = range {
            underlay.set_window(lo, hi)?;
        }
        Ok(Some((Arc::new(underlay), source)))
    }

    /// Each montage panel's underlay, the one volume read once, on the panel's slice
    /// plane placed as the underlay plane setting says; None each without an underlay.
    pub fn panel_underlays<'a>(
        &self,
        volume: &Volume,
        scenes: impl IntoIterator<Item = &'a VolumeScene>,
    ) -> Result<Vec<Option<Underlay>>> {
        let underlay = self.underlay_volume()?;
        let placement = self.underlay_placement()?;
        scenes
            .into_iter()
            .map(|scene| match &underlay {
                Some((underlay, source)) => {
                    view_underlay(underlay.clone(), *source, volume, scene, placement).map(Some)
                }
                None => Ok(None),
            })
            .collect()
    }

    /// The underlay of the view `scene` of `volume`, on its slice planes placed as the
    /// underlay plane setting says (behind the glyphs by default).
    fn underlay(&self, volume: &Volume, scene: &VolumeScene) -> Result<Option<Underlay>> {
        let Some((underlay, source)) = self.underlay_volume()? else {
            return Ok(None);
        };
        let placement = self.underlay_placement()?;
        view_underlay(underlay, source, volume, scene, placement).map(Some)
    }

    /// The panels of a montage of `volume` at the image size `image` (the views, or the
    /// lightbox's slices), each as the options of its single view (the slice in voxel
    /// axes, the mask read), without building their scenes: the viewer builds and
    /// rebuilds each panel as its slice moves.
    pub fn montage_plan(&self, volume: &Volume, image: ImageRequest) -> Result<MontagePlan> {
        self.check_montage()?;
        if !self.is_montage() {
            return Err(Error::Call {
                call: "VolumeRequest::montage",
                expected: "a request with views or a lightbox",
            });
        }
        let mut options = self.options(image)?;
        options.mask = self.read_mask()?;
        options.peaks = self.read_peaks()?;
        options.tracks = self.read_tracks()?;
        let mut plan = self.plan(volume, &options)?;
        if self.views.is_some() {
            // The viewer builds each panel itself: an empty middle slice is moved (or its
            // view left out) here, as `montage` does for `render`.
            let mut panels = Vec::with_capacity(plan.panels.len());
            for mut options in plan.panels {
                match volume_scene(volume, &options) {
                    Err(err) if options.slice.index.is_none() && is_nothing_to_draw(&err) => {
                        let (found, note) = nearest_slice_with_glyphs(volume, &options);
                        plan.notes.push(note.into());
                        if let Some((index, _)) = found {
                            options.slice.index = Some(index);
                            panels.push(options);
                        }
                    }
                    Err(err) => return Err(err),
                    Ok(_) => panels.push(options),
                }
            }
            if panels.is_empty() {
                return Err(Error::setting(
                    Setting::Views,
                    format!("no view of {} holds a glyph", volume.file),
                ));
            }
            plan.columns = panels.len();
            plan.panels = panels;
        }
        Ok(plan)
    }

    /// Each panel's options (from `options`, the montage's) and the grid's columns.
    fn plan(&self, volume: &Volume, options: &VolumeOptions) -> Result<MontagePlan> {
        let slices = match (&self.views, self.lightbox) {
            (Some(views), _) => parse_views(views)?,
            (None, count) => lightbox_slices(volume, options, count.unwrap_or(1))?,
        };
        let mut panels = Vec::with_capacity(slices.len());
        let mut notes = Vec::new();
        for slice in slices {
            let mut options = options.clone();
            options.slice = slice;
            if let Some(note) = slice_in_voxels(&mut options, volume)?.map(Into::into)
                && !notes.contains(&note)
            {
                notes.push(note);
            }
            panels.push(options);
        }
        let columns = match self.lightbox {
            Some(count) => (count as f64).sqrt().ceil() as usize,
            None => panels.len(),
        };
        Ok(MontagePlan {
            panels,
            columns,
            notes,
        })
    }

    /// The panels of the views, or of the lightbox's slices (captioned with their
    /// slice), each with the underlay on its plane. A view at its default (middle) slice
    /// that holds no glyph is drawn at the nearest slice that holds one, or left out when
    /// none does, with a note either way; only a montage left with no panel is an error.
    fn montage(&self, volume: &Volume, options: &VolumeOptions) -> Result<VolumeMontage> {
        let mut plan = self.plan(volume, options)?;
        let mut panels = Vec::with_capacity(plan.panels.len());
        let mut first_error = None;
        for options in &plan.panels {
            match volume_scene(volume, options) {
                Ok(scene) => panels.push(scene),
                Err(err)
                    if self.views.is_some()
                        && options.slice.index.is_none()
                        && is_nothing_to_draw(&err) =>
                {
                    let (found, note) = nearest_slice_with_glyphs(volume, options);
                    plan.notes.push(note.into());
                    panels.extend(found.map(|(_, scene)| scene));
                    first_error.get_or_insert(err);
                }
                Err(err) => return Err(err),
            }
        }
        if panels.is_empty()
            && let Some(err) = first_error
        {
            return Err(err);
        }
        let columns = if self.views.is_some() {
            panels.len()
        } else {
            plan.columns
        };
        let underlays = self.panel_underlays(volume, panels.iter())?;
        let captions = panels
            .iter()
            .map(|scene| {
                let region = &scene.region;
                let letter = ["i", "j", "k"][region.slice.voxel_axis()];
                self.lightbox
                    .is_some()
                    .then(|| format!("{letter}={}", region.index))
            })
            .collect();
        let mut report = super::VolumeReport::default();
        for panel in &panels {
            report.add(&panel.report);
        }
        let mut notes = volume.notes.clone();
        notes.extend(plan.notes);
        Ok(VolumeMontage {
            file: volume.file.clone(),
            warnings: report.warnings(&volume.file),
            panels,
            underlays,
            captions,
            columns,
            notes,
        })
    }
}

/// The index and scene of the slice of `options`' plane nearest its middle that holds a
/// glyph (`None` when no slice does), with a note that says which was drawn.
fn nearest_slice_with_glyphs(
    volume: &Volume,
    options: &VolumeOptions,
) -> (Option<(usize, VolumeScene)>, String) {
    let axis = options.slice.axis;
    let voxel = axis.voxel_axis();
    let (letter, length) = (["i", "j", "k"][voxel], volume.dims[voxel]);
    let middle = length / 2;
    let nearest = (1..length)
        .flat_map(|offset| [middle.checked_add(offset), middle.checked_sub(offset)])
        .flatten()
        .filter(|&index| index < length);
    for index in nearest {
        let mut moved = options.clone();
        moved.slice.index = Some(index);
        if let Ok(scene) = volume_scene(volume, &moved) {
            let note = format!(
                "{}: the middle {} slice ({letter}={middle}) holds no glyph; drawn at \
                 {letter}={index}, the nearest that does",
                volume.file,
                axis.name()
            );
            return (Some((index, scene)), note);
        }
    }
    let note = format!(
        "{}: no {} slice holds a glyph; that view is left out",
        volume.file,
        axis.name()
    );
    (None, note)
}

/// `count` slices of the slice plane, evenly spaced: slice k at the centre of the k-th
/// of `count` equal parts of the axis, floor((k + 1/2) n / count).
fn lightbox_slices(volume: &Volume, options: &VolumeOptions, count: usize) -> Result<Vec<Slice>> {
    let mut plane = options.clone();
    slice_in_voxels(&mut plane, volume)?;
    let axis = plane.slice.axis;
    let length = volume.dims[axis.voxel_axis()];
    if count > length {
        return Err(Error::setting_value(
            Setting::Lightbox,
            count,
            format!(
                "the {} plane has {length} slices in {}",
                axis.name(),
                volume.file
            ),
        ));
    }
    Ok((0..count)
        .map(|k| Slice {
            axis: options.slice.axis,
            index: Some(((2 * k + 1) * length) / (2 * count)),
        })
        .collect())
}

/// Turns the world plane the slice names into the voxel axis closest to it, with a note
/// when that is not the axis of the same name (a volume not stored axially), and an error
/// in the plane's terms when the index is outside that axis.
fn slice_in_voxels(options: &mut VolumeOptions, volume: &Volume) -> Result<Option<String>> {
    let named = options.slice;
    let axis = named
        .axis
        .world_plane_in_voxels(volume.voxel_to_world.linear());
    options.slice.axis = axis;
    if axis == named.axis || options.slices.is_some() {
        return Ok(None);
    }
    let voxel = axis.voxel_axis();
    let (letter, length) = (["i", "j", "k"][voxel], volume.dims[voxel]);
    if let Some(index) = named.index
        && index >= length
    {
        return Err(Error::input(
            &volume.file,
            format!("dim[{}]", voxel + 1),
            glyphcast::message![
                Setting::Slice.with(named),
                format!(
                    ": the {} plane is the slice of constant {letter} in this volume, which has \
                 {length} voxels along {letter} (0..={})",
                    named.axis.name(),
                    length.saturating_sub(1)
                )
            ],
        ));
    }
    Ok(Some(format!(
        "{}: the {} plane is the slice of constant {letter} in this volume",
        volume.file,
        named.axis.name(),
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::SliceAxis;

    #[test]
    fn views_parse_and_refuse_naming_the_setting() {
        let views = parse_views("coronal:3, axial").expect("two views");
        assert_eq!(views[0].axis, SliceAxis::Coronal);
        assert_eq!(views[0].index, Some(3));
        assert_eq!(views[1].axis, SliceAxis::Axial);
        for (text, message) in [
            ("axial,axial", "views 'axial,axial': axial is listed twice"),
            (
                "axial,oblique",
                "views 'axial,oblique': 'oblique' is not axial, coronal or sagittal \
                 (optionally :INDEX)",
            ),
        ] {
            let err = parse_views(text).expect_err(text);
            assert_eq!(err.setting_of(), Some(Setting::Views));
            assert_eq!(err.to_string(), message);
        }
    }
}
