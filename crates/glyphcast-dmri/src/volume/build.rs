//! A volume slice (three slices, or a block of voxels) as a [`Scene`]: select voxels,
//! reorient each glyph into world axes (voxel-frame coefficients only), measure it, drop
//! what cannot or should not be drawn, scale, and frame.
//!
//! Left out, and counted in the [`VolumeReport`] rather than failing: voxels outside the
//! mask, voxels with a NaN or infinite coefficient (the usual background of a fit; the
//! CLI prints their count as a warning), glyphs that are exactly zero (nothing to draw)
//! and glyphs whose max radius is below `min_amplitude`. A selection that leaves no glyph
//! at all is an error: an empty picture would look like a rendering fault.
use glyphcast::parallel::{Progress, map_chunks_with_progress};
use std::ops::Range;
use std::str::FromStr;

use glam::DVec3;

use super::amplitude::shape_radius;
use super::framing::{
    Framing, ImageRequest, Orientation, ViewProjection, frame_block, frame_region, frame_volume,
};
use super::input::{CoefficientFrame, Mask, Volume, show_shape};
use super::peaks::{ViewPeaks, peak_set};
use super::reorient::Reorientation;
use super::selection::{Slice, SliceRegion, Slices, VoxelRanges, show_block};
use super::tracks::{ViewTracks, view_tubes};
use glyphcast::glyph::ellipsoid::ELLIPSOID_LAYOUT;
use glyphcast::glyph::{GlyphShape, NegativeMode};
use glyphcast::render::peaks::PeakSet;
use glyphcast::scene::{GlyphKind, GlyphSet, Scene, fits_float32};
use glyphcast::{Error, Result, Setting};

/// Default world radius of the largest glyph, as a fraction of the smallest voxel size:
/// the largest glyph spans 0.9 of a voxel.
pub const DEFAULT_SCALE_FRACTION: f64 = 0.45;

/// The most glyphs a block view draws ([`VolumeOptions::block`]): voxels of the block
/// that the mask keeps and whose coefficients are finite. A block shows its outer glyphs
/// and hides the rest; one of a whole brain would take minutes a frame on a software
/// rasteriser and show only its surface, so it is refused, naming the voxel ranges and
/// the mask that choose a smaller one.
pub const MAX_BLOCK_GLYPHS: usize = 100_000;

/// The robust normalisation's reference: this percentile of the glyphs' max radii ...
pub const ROBUST_PERCENTILE: f64 = 99.0;
/// ... times this factor, if that is below the largest radius.
pub const ROBUST_FACTOR: f64 = 1.5;

/// The square-root sizing's reference: this percentile of the glyphs' max radii is
/// drawn at `scale` ([`Normalisation::Sqrt`]).
pub const SQRT_PERCENTILE: f64 = 95.0;

/// How glyph sizes relate to the data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Normalisation {
    /// The default: the glyph at the [`SQRT_PERCENTILE`]th percentile of the radii is
    /// drawn with radius `scale`, a smaller one with `scale` times the square root of
    /// its radius over that one's (a glyph a quarter as large is drawn half as large),
    /// a larger one with `scale` (counted in the report). Amplitude still orders the
    /// sizes, and a slice of fibre ODFs whose median glyph is a third of the largest
    /// shows it at more than half a voxel instead of a speck under a few large ones.
    #[default]
    Sqrt,
    /// One factor for all drawn glyphs, robust to a few outliers: glyphs larger than
    /// [`ROBUST_FACTOR`] times the [`ROBUST_PERCENTILE`]th percentile of the radii are
    /// outliers (counted in the report) and drawn with radius `scale`; the largest of
    /// the others becomes `scale`, so an outlier changes no other glyph's size. For data
    /// without outliers this is [`Normalisation::Global`].
    Robust,
    /// One factor for all drawn glyphs: the largest has radius `scale`.
    Global,
    /// Every glyph's max radius becomes `scale`.
    PerGlyph,
    /// Radius = amplitude * `scale` (data units times `scale`).
    None,
}

/// Everything about a volume view except the volume itself.
#[derive(Clone, Debug, Default)]
pub struct VolumeOptions {
    /// The slice drawn (`--slice axial:4`); the middle axial slice by default.
    pub slice: Slice,
    /// Three orthogonal slices instead of `slice`: one glyph set per slice (sagittal,
    /// coronal, axial; a slice with nothing to draw has none), framed by a perspective
    /// camera from anterior-superior-left whatever `projection` says.
    pub slices: Option<Slices>,
    /// Every voxel of `voxels` (the whole volume without ranges) instead of `slice`, in
    /// 3D: one glyph set, seen by a perspective camera from the corner `slices` are seen
    /// from whatever `projection` says, at the distance where the block's corners are in
    /// view ([`frame_block`](super::frame_block)); at most [`MAX_BLOCK_GLYPHS`] glyphs.
    pub block: bool,
    /// Index ranges the drawn voxels must lie in (`--voxels`).
    pub voxels: VoxelRanges,
    /// Only voxels the mask keeps are drawn (`--mask`).
    pub mask: Option<Mask>,
    /// World radius of the largest glyph (default: 0.45 * the smallest voxel size).
    pub scale: Option<f64>,
    /// How glyph sizes follow the data (`--norm`).
    pub norm: Normalisation,
    /// The polynomial glyph, or the DTI ellipsoid (order-2 tensor volumes only); the
    /// ellipsoid's size is its longest semi-axis, sqrt(lambda_1).
    pub shape: GlyphShape,
    /// Glyphs with max radius below this (data units) are left out.
    pub min_amplitude: f64,
    /// SH only: drop bands above this one.
    pub lmax: Option<u32>,
    /// Orthographic or perspective framing.
    pub projection: ViewProjection,
    /// Which side of the image the subject's right is on, in every view.
    pub orientation: Orientation,
    /// The image size asked for; a missing side follows the slice's aspect.
    pub image: ImageRequest,
    /// Fibre peaks drawn in the voxels of the slices, if any (on the volume's grid;
    /// alone where the volume only stands for their grid, [`Volume::grid_of_peaks`]).
    pub peaks: Option<ViewPeaks>,
    /// Streamlines drawn as tubes with the glyphs, if any (`volume::tracks`): on a slice
    /// view the parts within their slab of the slices' planes.
    pub tracks: Option<ViewTracks>,
}

/// What happened to the voxels of the selection.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VolumeReport {
    /// Voxels of the slice (or slices, each voxel once) within the ranges.
    pub selected: usize,
    /// Selected voxels the mask leaves out.
    pub masked_out: usize,
    /// Voxels with a NaN or infinite coefficient.
    pub non_finite: usize,
    /// Glyphs that are zero everywhere.
    pub zero: usize,
    /// Glyphs whose largest radius is below `min_amplitude`.
    pub below_min_amplitude: usize,
    /// Glyphs in the scene.
    pub drawn: usize,
    /// Glyphs larger than the robust normalisation's limit, drawn at the limit's size.
    pub capped: usize,
}

impl VolumeReport {
    /// Adds `other`'s counts to these (the panels of a montage, reported as one).
    pub fn add(&mut self, other: &VolumeReport) {
        self.selected += other.selected;
        self.masked_out += other.masked_out;
        self.non_finite += other.non_finite;
        self.zero += other.zero;
        self.below_min_amplitude += other.below_min_amplitude;
        self.drawn += other.drawn;
        self.capped += other.capped;
    }

    /// What the user is warned of about the voxels of `file`, one line each, the same in
    /// every front end (the command line prints them, Python warns): voxels left out
    /// for NaN or infinite coefficients, and outliers capped by the robust
    /// normalisation. Lines may mention settings, which each front end spells.
    pub fn warnings(&self, file: &str) -> Vec<glyphcast::error::Message> {
        let mut lines = Vec::new();
        if self.non_finite > 0 {
            lines.push(
                format!(
                    "{file}: {} voxel(s) with NaN or infinite coefficients left out",
                    self.non_finite
                )
                .into(),
            );
        }
        if self.capped > 0 {
            lines.push(glyphcast::message![
                format!(
                    "{file}: {} glyph(s) larger than {ROBUST_FACTOR} times the \
                 {ROBUST_PERCENTILE}th percentile of the glyph sizes drawn at that size \
                 (outliers; ",
                    self.capped
                ),
                Setting::Norm.with("global"),
                " sizes every glyph by one factor)"
            ]);
        }
        lines
    }
}

/// The scene of a volume view, and how it was selected.
#[derive(Clone, Debug)]
pub struct VolumeScene {
    /// The glyphs (one set per slice), the framing camera and the image size.
    pub scene: Scene,
    /// What happened to the voxels of the selection.
    pub report: VolumeReport,
    /// The slice's region; with three slices, the first (sagittal) one.
    pub region: SliceRegion,
    /// Every slice's region: one, or sagittal, coronal and axial; a block's axial slices,
    /// bottom to top.
    pub regions: Vec<SliceRegion>,
    /// The voxel box of a block view (index ranges along i, j, k), None for slices.
    pub block: Option<[Range<usize>; 3]>,
    /// The largest world radius of a drawn glyph: how far the glyphs reach out of
    /// their slice plane (an underlay drawn behind them goes that far back).
    pub glyph_radius: f64,
    /// The peaks of the slices, if asked for.
    pub peaks: Option<PeakSet>,
}

impl FromStr for Normalisation {
    type Err = Error;

    fn from_str(text: &str) -> Result<Self> {
        match text {
            "sqrt" => Ok(Normalisation::Sqrt),
            "robust" => Ok(Normalisation::Robust),
            "global" => Ok(Normalisation::Global),
            "per-glyph" => Ok(Normalisation::PerGlyph),
            "none" => Ok(Normalisation::None),
            _ => Err(Error::setting_value(
                Setting::Norm,
                format!("'{}'", glyphcast::error::quoted(text)),
                "expected sqrt, robust, global, per-glyph or none",
            )),
        }
    }
}

/// One glyph on its way into the scene.
struct Glyph {
    center: DVec3,
    coeffs: Vec<f64>,
    radius: f64,
}

/// The camera and image size of the single slice `options.slice` (with its voxel
/// ranges) of `volume`, as [`volume_scene`] frames it, without building the glyphs: the
/// viewer shifts its camera by it when a slice moves, and sizes a montage's cells by it.
pub fn slice_framing(volume: &Volume, options: &VolumeOptions) -> Result<Framing> {
    let region = SliceRegion::new(volume.dims, options.slice, &options.voxels, &volume.file)?;
    frame_region(
        &region,
        &volume.voxel_to_world,
        options.projection,
        options.orientation,
        options.image,
    )
}

/// The scene showing `options.slice` (or `options.slices`) of `volume`.
pub fn volume_scene(volume: &Volume, options: &VolumeOptions) -> Result<VolumeScene> {
    volume_scene_with_progress(volume, options, None)
}

/// [`volume_scene`], reporting the sizing of the glyphs to `progress`.
pub fn volume_scene_with_progress(
    volume: &Volume,
    options: &VolumeOptions,
    progress: Option<&Progress>,
) -> Result<VolumeScene> {
    check_options(volume, options)?;
    let block = options
        .block
        .then(|| options.voxels.block(volume.dims, &volume.file))
        .transpose()?;
    let region = |slice| SliceRegion::new(volume.dims, slice, &options.voxels, &volume.file);
    let regions = match (&block, options.slices) {
        (Some(block), _) => SliceRegion::block_slices(block),
        (None, Some(slices)) => (0..3)
            .map(|axis| region(slices.slice(axis)))
            .collect::<Result<Vec<_>>>()?,
        (None, None) => vec![region(options.slice)?],
    };
    let kind = truncated_kind(volume, options.lmax)?;
    let map = &volume.voxel_to_world;
    let reorientation = reorientation(volume)?.for_kind(kind)?;
    let mut report = VolumeReport::default();
    // The voxels that may become glyphs, per slice; a block's are one set.
    let mut candidates: Vec<Vec<([usize; 3], Vec<f64>)>> = Vec::with_capacity(regions.len());
    for (n, region) in regions.iter().enumerate() {
        if n == 0 || block.is_none() {
            candidates.push(Vec::new());
        }
        let Some(kept) = candidates.last_mut() else {
            break;
        };
        // A voxel where two slices cross belongs to the first of them only (a block's
        // slices do not cross).
        for voxel in region.voxels() {
            if volume.is_peaks_grid()
                || (block.is_none() && regions[..n].iter().any(|earlier| earlier.contains(voxel)))
            {
                continue;
            }
            report.selected += 1;
            if options.mask.as_ref().is_some_and(|mask| !mask.keeps(voxel)) {
                report.masked_out += 1;
                continue;
            }
            let mut coeffs = volume.coefficients(voxel);
            if coeffs.iter().any(|c| !c.is_finite()) {
                report.non_finite += 1;
                continue;
            }
            // Past the limit a block's voxels are only counted, for the refusal.
            if block.is_some()
                && report.selected - report.masked_out - report.non_finite > MAX_BLOCK_GLYPHS
            {
                continue;
            }
            coeffs.truncate(kind.coefficient_count());
            check_float32(volume, voxel, &coeffs)?;
            let coeffs = reorientation.apply(&coeffs)?;
            kept.push((voxel, coeffs));
        }
    }
    if let Some(block) = &block {
        let glyphs = report.selected - report.masked_out - report.non_finite;
        if glyphs > MAX_BLOCK_GLYPHS {
            return Err(block_too_large(volume, block, glyphs, &report));
        }
    }
    let mut glyphs: Vec<Vec<Glyph>> = Vec::with_capacity(candidates.len());
    for candidates in candidates {
        let radii = map_chunks_with_progress(&candidates, "sizing", progress, |(_, coeffs)| {
            shape_radius(kind, options.shape, coeffs)
        })?;
        let mut drawn = Vec::new();
        for ((voxel, coeffs), radius) in candidates.into_iter().zip(radii) {
            if radius <= 0.0 {
                report.zero += 1;
            } else if radius < options.min_amplitude {
                report.below_min_amplitude += 1;
            } else {
                let center = map.voxel_center(DVec3::from_array(voxel.map(|v| v as f64)));
                drawn.push(Glyph {
                    center,
                    coeffs,
                    radius,
                });
            }
        }
        glyphs.push(drawn);
    }
    report.drawn = glyphs.iter().map(Vec::len).sum();
    let selection = shown_selection(&regions, block.as_ref());
    if report.drawn == 0 && !volume.is_peaks_grid() {
        return Err(nothing_to_draw(volume, &selection, &report));
    }
    let scale = options
        .scale
        .unwrap_or_else(|| DEFAULT_SCALE_FRACTION * map.voxel_sizes().min_element());
    let framing = match (&block, options.slices) {
        // The block's voxel boxes, seen from the corner the three slices are seen from.
        (Some(block), _) => frame_block(block, map, options.orientation, options.image)?,
        (None, Some(_)) => {
            // The box the three slices span: each region is whole along the other axes.
            let span = [
                regions[1].ranges[0].clone(),
                regions[0].ranges[1].clone(),
                regions[0].ranges[2].clone(),
            ];
            frame_volume(&span, map, options.orientation, options.image)?
        }
        (None, None) => frame_region(
            &regions[0],
            map,
            options.projection,
            options.orientation,
            options.image,
        )?,
    };
    let peaks = options
        .peaks
        .as_ref()
        .map(|peaks| {
            let (camera, height) = (&framing.camera, framing.image.height);
            peak_set(peaks, &regions, options.mask.as_ref(), camera, height)
        })
        .transpose()?;
    if volume.is_peaks_grid() && peaks.as_ref().is_none_or(|p| p.segments.is_empty()) {
        return Err(no_peak_to_draw(volume, &selection));
    }
    // The tubes are capsules of the peaks' pass: one set, one depth test.
    let peaks = match &options.tracks {
        Some(tracks) => {
            let tubes = view_tubes(tracks, &regions, block.is_some(), map)?;
            let mut all = peaks.unwrap_or_default();
            all.extend(tubes);
            Some(all)
        }
        None => peaks,
    };
    // Global normalisation is over all slices together.
    let radii: Vec<f64> = glyphs.iter().flatten().map(|g| g.radius).collect();
    let reference = match options.norm {
        Normalisation::Robust => robust_reference(&radii),
        Normalisation::Sqrt => percentile(&radii, SQRT_PERCENTILE),
        _ => radii.iter().copied().fold(0.0, f64::max),
    };
    // The square-root sizing draws its top percentiles at the scale by design: only the
    // robust one's outliers are reported.
    if options.norm == Normalisation::Robust {
        report.capped = radii.iter().filter(|&&r| r > reference).count();
    }
    let glyph_sets: Vec<GlyphSet> = glyphs
        .into_iter()
        .filter(|g| !g.is_empty())
        .map(|g| glyph_set(kind, g, scale, reference, options))
        .collect();
    let glyph_radius = glyph_sets
        .iter()
        .flat_map(|set| set.scales.iter())
        .zip(&radii)
        .map(|(scale, radius)| scale * radius)
        .fold(0.0, f64::max);
    Ok(VolumeScene {
        scene: Scene {
            glyph_sets,
            camera: framing.camera,
            image: framing.image,
        },
        report,
        region: regions[0].clone(),
        regions,
        block,
        glyph_radius,
        peaks,
    })
}

/// Refuses a voxel's coefficient beyond float32's range (a float64 image can hold
/// one): a scene keeps them as they are, and glyphcast draws, and reads saved scenes,
/// in float32 (`scene::MAX_SCENE_MAGNITUDE`).
fn check_float32(volume: &Volume, voxel: [usize; 3], coeffs: &[f64]) -> Result<()> {
    match coeffs.iter().position(|c| !fits_float32(*c)) {
        None => Ok(()),
        Some(c) => Err(Error::input(
            &volume.file,
            format!("voxel {voxel:?}, coefficient {c}"),
            format!(
                "{:?} is beyond float32's range (magnitude at most {:e}), in which glyphs \
                 are drawn",
                coeffs[c],
                f32::MAX
            ),
        )),
    }
}

/// The `p`th percentile of `radii` by the lower nearest rank (the value at index
/// floor(p/100 (n - 1)) of the sorted radii); 0 for none.
pub fn percentile(radii: &[f64], p: f64) -> f64 {
    let mut sorted = radii.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * sorted.len().saturating_sub(1) as f64).floor() as usize;
    sorted.get(rank).copied().unwrap_or(0.0)
}

/// The radius that [`Normalisation::Robust`] draws at `scale`: the largest of `radii`
/// that is no outlier, an outlier being larger than [`ROBUST_FACTOR`] times their
/// [`ROBUST_PERCENTILE`]th percentile. The percentile is the lower nearest rank (the
/// value at index floor(p/100 (n - 1)) of the sorted radii), so that one outlier among
/// few glyphs is never its own reference; and since the reference is a glyph's own
/// radius, not the limit, the other glyphs are drawn as large as without the outlier.
pub fn robust_reference(radii: &[f64]) -> f64 {
    let largest = radii.iter().copied().fold(0.0, f64::max);
    if radii.len() < 2 {
        return largest;
    }
    let mut sorted = radii.to_vec();
    sorted.sort_by(f64::total_cmp);
    let rank = ((ROBUST_PERCENTILE / 100.0) * (sorted.len() - 1) as f64).floor() as usize;
    let limit = ROBUST_FACTOR * sorted[rank];
    if limit > 0.0 {
        sorted
            .iter()
            .rev()
            .copied()
            .find(|&r| r <= limit)
            .unwrap_or(largest)
    } else {
        largest
    }
}

/// What turns the volume's glyphs into world axes: the affine's orthogonal factor for
/// voxel-frame coefficients, nothing for world-frame ones.
fn reorientation(volume: &Volume) -> Result<Reorientation> {
    if volume.frame == CoefficientFrame::World {
        return Ok(Reorientation::new(glam::DMat3::IDENTITY));
    }
    let rotation = volume.voxel_to_world.orthogonal_factor().ok_or_else(|| {
        Error::input(
            &volume.file,
            "affine",
            "the polar decomposition of the affine did not converge",
        )
    })?;
    Ok(Reorientation::new(rotation))
}

fn check_options(volume: &Volume, options: &VolumeOptions) -> Result<()> {
    if let Some(peaks) = &options.peaks {
        peaks
            .volume
            .check_grid(&volume.file, volume.dims, &volume.voxel_to_world)?;
    }
    if let Some(scale) = options.scale
        && !(scale.is_finite() && scale > 0.0)
    {
        return Err(Error::setting_value(
            Setting::Scale,
            scale,
            "must be a positive number",
        ));
    }
    if options.shape == GlyphShape::Ellipsoid && volume.kind != GlyphKind::Tensor(ELLIPSOID_LAYOUT)
    {
        return Err(Error::setting_value(
            Setting::Glyph,
            "ellipsoid",
            format!(
                "draws order-2 symmetric tensors (DTI), and {} holds a {}",
                volume.file, volume.kind
            ),
        ));
    }
    if !(options.min_amplitude.is_finite() && options.min_amplitude >= 0.0) {
        return Err(Error::setting_value(
            Setting::MinAmplitude,
            options.min_amplitude,
            "must be a number >= 0",
        ));
    }
    if let Some(mask) = &options.mask
        && mask.dims != volume.dims
    {
        return Err(Error::input(
            &mask.file,
            "dim",
            format!(
                "the mask is {} but the volume {} is {}",
                show_shape(&mask.dims),
                volume.file,
                show_shape(&volume.dims)
            ),
        ));
    }
    Ok(())
}

/// The volume's kind with SH bands above `lmax` dropped.
fn truncated_kind(volume: &Volume, lmax: Option<u32>) -> Result<GlyphKind> {
    match (volume.kind, lmax) {
        (_, None) => Ok(volume.kind),
        (
            GlyphKind::Sh {
                band,
                basis,
                legacy,
            },
            Some(lmax),
        ) => {
            if lmax % 2 != 0 || lmax > band {
                return Err(Error::input(
                    &volume.file,
                    Setting::Lmax.name(),
                    glyphcast::message![
                        Setting::Lmax.with(lmax),
                        format!(" must be even and at most the file's band {band}")
                    ],
                ));
            }
            Ok(GlyphKind::Sh {
                band: lmax,
                basis,
                legacy,
            })
        }
        (GlyphKind::Tensor(_), Some(_)) => {
            Err(Error::setting(Setting::Lmax, "applies to SH volumes only"))
        }
    }
}

/// How the error of a selection with no glyph starts ([`is_nothing_to_draw`]).
const NOTHING_TO_DRAW: &str = "no glyph to draw in the ";

/// Whether `err` is [`volume_scene`]'s refusal of a selection that holds no glyph.
pub fn is_nothing_to_draw(err: &Error) -> bool {
    matches!(err, Error::Input { field, message, .. }
        if field == "voxels" && message.to_string().starts_with(NOTHING_TO_DRAW))
}

/// What a view shows, in messages: `slice k=3` (`slice i=1, j=2, k=3` for three slices)
/// or `block 0:10,0:10,2:8`.
fn shown_selection(regions: &[SliceRegion], block: Option<&[Range<usize>; 3]>) -> String {
    if let Some(block) = block {
        return format!("block {}", show_block(block));
    }
    let slices: Vec<String> = regions
        .iter()
        .map(|r| format!("{}={}", ["i", "j", "k"][r.slice.voxel_axis()], r.index))
        .collect();
    format!("slice {}", slices.join(", "))
}

/// A block of more than [`MAX_BLOCK_GLYPHS`] glyphs, refused.
fn block_too_large(
    volume: &Volume,
    block: &[Range<usize>; 3],
    glyphs: usize,
    report: &VolumeReport,
) -> Error {
    Error::input(
        &volume.file,
        Setting::Block.name(),
        glyphcast::message![
            format!(
                "the block {} holds {glyphs} voxels with finite coefficients{}, more than the \
                 {MAX_BLOCK_GLYPHS} glyphs a block draws (only its outer glyphs would be \
                 seen): give a smaller block with ",
                show_block(block),
                if report.masked_out > 0 {
                    " in the mask"
                } else {
                    ""
                }
            ),
            Setting::Voxels,
            " (i0:i1,j0:j1,k0:k1), or ",
            Setting::Mask
        ],
    )
}

fn nothing_to_draw(volume: &Volume, selection: &str, report: &VolumeReport) -> Error {
    Error::input(
        &volume.file,
        "voxels",
        glyphcast::message![
            format!(
                "{NOTHING_TO_DRAW}{} voxels selected ({} of them masked out, {} not finite, \
             {} zero, {} below ",
                report.selected,
                report.masked_out,
                report.non_finite,
                report.zero,
                report.below_min_amplitude
            ),
            Setting::MinAmplitude,
            format!(") in {selection}")
        ],
    )
}

fn no_peak_to_draw(volume: &Volume, selection: &str) -> Error {
    Error::input(
        &volume.file,
        "data",
        format!("no peak to draw in {selection} (NaN or masked out everywhere there)"),
    )
}

/// The glyphs as one set, sized by `norm` so that the `reference` radius becomes
/// `scale` (a robust one caps the glyphs above it at `scale`).
fn glyph_set(
    kind: GlyphKind,
    glyphs: Vec<Glyph>,
    scale: f64,
    reference: f64,
    options: &VolumeOptions,
) -> GlyphSet {
    let scales = glyphs
        .iter()
        .map(|g| match options.norm {
            Normalisation::Robust => scale / g.radius.max(reference),
            // scale sqrt(r / reference) / r, at most scale / r.
            Normalisation::Sqrt if g.radius > 0.0 && reference > 0.0 => {
                scale * (g.radius / reference).sqrt().min(1.0) / g.radius
            }
            Normalisation::Sqrt => scale / reference.max(g.radius),
            Normalisation::Global => scale / reference,
            Normalisation::PerGlyph => scale / g.radius,
            Normalisation::None => scale,
        })
        .collect();
    let (centers, coeffs) = glyphs.into_iter().map(|g| (g.center, g.coeffs)).unzip();
    GlyphSet {
        kind,
        negative: NegativeMode::Abs,
        shape: options.shape,
        centers,
        scales,
        coeffs,
    }
}
