//! The figures of the set, each a montage (`render::compose::montage`) of single-view panels
//! built by `volume::volume_scene`, as `render --views` builds its panels: the ODF
//! mosaic (rows axial, coronal, sagittal; three cuts each), the peaks mosaic (the same
//! panels with the peaks drawn over them) and one zoomed figure per region (its cube
//! seen axially, coronally and sagittally through its centre).
//!
//! Every glyph of the set is sized on one scale, so that sizes compare across panels and
//! figures: proportional to the glyph's largest radius, up to a full size that the
//! larger half of the set's glyphs share ([`size_alike`]).
use std::path::Path;
use std::sync::Arc;

use super::survey::{PlaneCuts, Region};
use crate::io::nifti::AffineSource;
use crate::io::tracks::Tractogram;
use crate::volume::{CoefficientFrame, UnderlayPlacement};
use crate::volume::{
    PeakStyle, PeaksColor, PeaksNorm, TrackShape, TrackStyle, TracksColor, ViewPeaks, ViewTracks,
    load_peaks, peak_set, view_tubes,
};
use crate::volume::{Slice, SliceAxis, Volume, VolumeOptions, VolumeScene, VoxelRanges};
use crate::volume::{view_underlay, volume_scene};
use glyphcast::glyph::NegativeMode;
use glyphcast::render::RenderSettings;
use glyphcast::render::compose::montage::prepare_montage;
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::render::underlay::{Underlay, UnderlayVolume};
use glyphcast::vk::Gpu;
use glyphcast::{Error, Result};

/// One figure of the set before rendering: its file, what it shows, and its panels.
pub struct FigurePlan {
    /// The PNG's name in the set's folder.
    pub file: String,
    /// A heading for the page.
    pub title: String,
    /// What a reader sees, for the page.
    pub caption: String,
    /// Each panel's options and caption, in reading order.
    pub panels: Vec<(VolumeOptions, String)>,
    /// Panels to a row.
    pub columns: usize,
}

/// A figure with its panels' scenes built.
pub struct BuiltFigure {
    /// The plan the scenes were built from.
    pub plan: FigurePlan,
    /// One scene per panel, in the plan's order.
    pub scenes: Vec<VolumeScene>,
}

/// A rendered figure.
pub struct Figure {
    /// The PNG's name in the set's folder.
    pub file: String,
    /// The heading the page shows above it.
    pub title: String,
    /// What a reader sees, for the page.
    pub caption: String,
    /// Each panel's caption, in reading order.
    pub panel_captions: Vec<String>,
    /// Panels to a row of the montage.
    pub columns: usize,
    /// The rendered montage with its edge labels.
    pub image: RenderedImage,
    /// Glyphs drawn in all panels.
    pub glyphs: usize,
}

/// The underlay image shared by every panel, with the source of its affine.
pub struct SharedUnderlay {
    /// The underlay slices, sampled once for every figure.
    pub volume: Arc<UnderlayVolume>,
    /// Which header fields placed the underlay in the world (its sform, qform or pixdim).
    pub source: AffineSource,
}

/// The ODF mosaic: a row per plane of `cuts`, a panel per cut, on `base`'s options.
pub fn mosaic_plan(base: &VolumeOptions, cuts: &[PlaneCuts]) -> FigurePlan {
    let mut panels = Vec::new();
    for plane in cuts {
        for &index in &plane.indices {
            let mut options = base.clone();
            options.slice = Slice {
                axis: plane.voxel_plane,
                index: Some(index),
            };
            let letter = ["i", "j", "k"][plane.voxel_plane.voxel_axis()];
            panels.push((options, format!("{} {letter}={index}", plane.plane.name())));
        }
    }
    let rows: Vec<String> = cuts
        .iter()
        .map(|c| {
            let letter = ["i", "j", "k"][c.voxel_plane.voxel_axis()];
            let indices: Vec<String> = c.indices.iter().map(usize::to_string).collect();
            format!("{} {letter} = {}", c.plane.name(), indices.join(", "))
        })
        .collect();
    FigurePlan {
        file: "odf-mosaic.png".into(),
        title: "ODF mosaic".into(),
        caption: format!(
            "Rows: axial, coronal, sagittal. Each row's three cuts are the slices at the \
             quartiles of the ODF amplitude of the voxels looked at ({}).",
            rows.join("; ")
        ),
        columns: cuts.iter().map(|c| c.indices.len()).max().unwrap_or(1),
        panels,
    }
}

/// The zoomed figure of `region` (rank `rank`, from 1): its cube through its centre
/// voxel, axially, coronally and sagittally.
pub fn zoom_plan(
    base: &VolumeOptions,
    volume: &Volume,
    region: &Region,
    rank: usize,
    world: [f64; 3],
) -> FigurePlan {
    let centre = region.centre();
    let mut ranges = VoxelRanges::default();
    for a in 0..3 {
        ranges.axes[a] = Some((
            Some(region.start[a]),
            Some(region.start[a] + region.size[a]),
        ));
    }
    let mut panels = Vec::new();
    for plane in [SliceAxis::Axial, SliceAxis::Coronal, SliceAxis::Sagittal] {
        let voxel_plane = plane.world_plane_in_voxels(volume.voxel_to_world.linear());
        let axis = voxel_plane.voxel_axis();
        let mut options = base.clone();
        options.voxels = ranges;
        options.slice = Slice {
            axis: voxel_plane,
            index: Some(region.slices[axis]),
        };
        let letter = ["i", "j", "k"][axis];
        panels.push((
            options,
            format!("{} {letter}={}", plane.name(), region.slices[axis]),
        ));
    }
    FigurePlan {
        file: format!("zoom-{rank}.png"),
        title: format!("Region {rank}"),
        caption: format!(
            "The {}x{}x{} voxels {} around voxel ({}, {}, {}), world ({:.1}, {:.1}, {:.1}) mm: \
             mean GFA {:.3}, mean ODF amplitude {:.4}; the region of rank {rank} by mean GFA.",
            region.size[0],
            region.size[1],
            region.size[2],
            region.ranges_text(),
            centre[0],
            centre[1],
            centre[2],
            world[0],
            world[1],
            world[2],
            region.mean_gfa,
            region.mean_amplitude
        ),
        panels,
        columns: 3,
    }
}

/// Builds every panel's scene of `plans`.
pub fn build(volume: &Volume, plans: Vec<FigurePlan>) -> Result<Vec<BuiltFigure>> {
    plans
        .into_iter()
        .map(|plan| {
            let scenes = plan
                .panels
                .iter()
                .map(|(options, _)| volume_scene(volume, options))
                .collect::<Result<Vec<_>>>()?;
            Ok(BuiltFigure { plan, scenes })
        })
        .collect()
}

/// The share of the set's glyphs drawn smaller than full size (see [`size_alike`]).
pub const FULL_SIZE_PERCENTILE: f64 = 0.5;

/// Sizes every glyph of `figures` on one scale (see the module notes): the panels were
/// built with per-glyph sizing (every glyph's largest radius r made the default scale
/// S: its scale factor is S / r), and each factor is now capped at S / R, with R the
/// [`FULL_SIZE_PERCENTILE`] of r over every glyph of the set. A glyph is then drawn
/// S r / R, proportional to its amplitude, up to the full size S (0.45 of a voxel)
/// that the larger half shares: the weaker half shows its amplitude, while outliers do
/// not shrink every other glyph to a dot (a whole brain's mosaic at 8 pixels a voxel
/// showed little more than dots with the 90th percentile).
pub fn size_alike(figures: &mut [BuiltFigure]) {
    let mut inverse: Vec<f64> = figures
        .iter()
        .flat_map(|f| &f.scenes)
        .flat_map(|s| &s.scene.glyph_sets)
        .flat_map(|set| set.scales.iter().map(|s| 1.0 / s))
        .filter(|q| q.is_finite())
        .collect();
    if inverse.is_empty() {
        return;
    }
    inverse.sort_by(f64::total_cmp);
    let at = ((inverse.len() - 1) as f64 * FULL_SIZE_PERCENTILE).round() as usize;
    let cap = 1.0 / inverse[at];
    for set in figures
        .iter_mut()
        .flat_map(|f| &mut f.scenes)
        .flat_map(|s| &mut s.scene.glyph_sets)
    {
        set.scales.iter_mut().for_each(|s| *s = s.min(cap));
    }
}

/// How every figure is drawn.
pub struct DrawContext<'a> {
    /// The device every figure is drawn on.
    pub gpu: &'a Gpu,
    /// Method, colour, samples and the rest, the same for every figure.
    pub settings: RenderSettings,
    /// Replaces every glyph set's negative-lobe mode, if given.
    pub negative: Option<NegativeMode>,
    /// The underlay drawn behind each panel's slice, if the set has one.
    pub underlay: Option<&'a SharedUnderlay>,
    /// The volume the scenes were built from, for the underlay's placement.
    pub volume: &'a Volume,
}

/// Renders `figure`: its panels as a montage, labelled at their edges, each over its
/// own slice's underlay if there is one.
pub fn render(
    context: &DrawContext,
    renderer: &mut HeadlessRenderer,
    figure: BuiltFigure,
) -> Result<Figure> {
    let BuiltFigure { plan, scenes } = figure;
    let underlays = match context.underlay {
        None => Vec::new(),
        Some(shared) => scenes
            .iter()
            .map(|scene| {
                // Behind the glyphs, as every slice view draws it by default.
                view_underlay(
                    shared.volume.clone(),
                    shared.source,
                    context.volume,
                    scene,
                    UnderlayPlacement::default(),
                )
                .map(Some)
            })
            .collect::<Result<Vec<Option<Underlay>>>>()?,
    };
    let glyphs = scenes.iter().map(|s| s.report.drawn).sum();
    let (scenes, peaks): (Vec<_>, Vec<_>) = scenes.into_iter().map(|s| (s.scene, s.peaks)).unzip();
    let mut prepared = prepare_montage(scenes, plan.columns, context.settings, context.negative)?;
    for (panel, peaks) in prepared.panels.iter_mut().zip(peaks) {
        panel.peaks = peaks;
    }
    let image = prepared.render_with_underlays(renderer, context.gpu, true, &underlays)?;
    if image.width == 0 || image.height == 0 {
        return Err(Error::input(plan.file, "image", "an empty figure"));
    }
    Ok(Figure {
        file: plan.file,
        title: plan.title,
        caption: plan.caption,
        panel_captions: plan.panels.into_iter().map(|(_, c)| c).collect(),
        columns: plan.columns,
        image,
        glyphs,
    })
}

/// How large the glyphs of the peaks mosaic are drawn against the ODF mosaic's, so that
/// the peaks reach out of the lobes they lie on.
pub const PEAKS_MOSAIC_GLYPH_SIZE: f64 = 0.75;

/// The share of the mosaic's peaks drawn shorter than full length (see [`peaks_mosaic`]).
pub const FULL_LENGTH_PERCENTILE: f64 = 0.5;

/// The peaks mosaic: the ODF mosaic's panels (`mosaic`, built and sized with the rest)
/// with the peaks of the image at `peaks` (checked against the ODFs' grid by the
/// caller) drawn over the glyphs in the same depth buffer, as `render --peaks` draws
/// them: white capsules through the voxel centres. The peaks are sized as the glyphs
/// are: in proportion to the amplitude up to a full length (half a voxel each way) that
/// the larger half of the drawn peaks share, so that a spurious small peak stays short
/// while an outlier does not shrink every other peak into its lobe; the glyphs are
/// drawn at [`PEAKS_MOSAIC_GLYPH_SIZE`] of their size in the ODF mosaic, so that every
/// full-length peak reaches out of its lobe.
pub fn peaks_mosaic(
    context: &DrawContext,
    renderer: &mut HeadlessRenderer,
    mosaic: &BuiltFigure,
    peaks: &Path,
    frame: Option<CoefficientFrame>,
) -> Result<Figure> {
    let volume = Arc::new(load_peaks(peaks, None, frame)?);
    let full = 0.5 * volume.voxel_to_world.voxel_sizes().min_element();
    let view = ViewPeaks {
        volume,
        style: PeakStyle {
            color: PeaksColor::Uniform([1.0, 1.0, 1.0]),
            norm: PeaksNorm::None,
            scale: Some(1.0),
            ..PeakStyle::default()
        },
    };
    let mut scenes = mosaic.scenes.clone();
    for scene in &mut scenes {
        let camera = &scene.scene.camera;
        let height = scene.scene.image.height;
        scene.peaks = Some(peak_set(&view, &scene.regions, None, camera, height)?);
        for set in &mut scene.scene.glyph_sets {
            set.scales
                .iter_mut()
                .for_each(|s| *s *= PEAKS_MOSAIC_GLYPH_SIZE);
        }
    }
    size_peaks_alike(&mut scenes, full);
    let plan = FigurePlan {
        file: "peaks-mosaic.png".into(),
        title: "Peaks mosaic".into(),
        caption: format!(
            "The ODF mosaic's panels with the peaks of {} drawn over the glyphs: white \
             capsules through the voxel centres, in proportion to the amplitude up to half \
             a voxel each way, which the larger half of the peaks reach; the glyphs at {} \
             times their size in the ODF mosaic.",
            peaks.display(),
            PEAKS_MOSAIC_GLYPH_SIZE
        ),
        panels: mosaic.plan.panels.clone(),
        columns: mosaic.plan.columns,
    };
    render(context, renderer, BuiltFigure { plan, scenes })
}

/// The streamlines drawn in the tracks mosaic: within half a voxel of each panel's slice,
/// tubes of a tenth of a voxel's radius.
const TRACKS_MOSAIC_SLAB_VOXELS: f64 = 0.5;
const TRACKS_MOSAIC_RADIUS_VOXELS: f64 = 0.1;

/// The tracks mosaic: the ODF mosaic's panels (`mosaic`) with the parts of the
/// streamlines of `tractogram` (read from `path`) within half a voxel of each panel's
/// slice drawn over the glyphs as tubes coloured by direction, in the same depth buffer
/// (`render --tracks` with a slab); the glyphs at the peaks mosaic's size, so that the
/// tubes show between the lobes.
pub fn tracks_mosaic(
    context: &DrawContext,
    renderer: &mut HeadlessRenderer,
    mosaic: &BuiltFigure,
    path: &Path,
    tractogram: &Arc<Tractogram>,
) -> Result<Figure> {
    let voxel = context.volume.voxel_to_world.voxel_sizes().min_element();
    let tracks = ViewTracks {
        tractogram: Arc::clone(tractogram),
        style: TrackStyle {
            radius: TRACKS_MOSAIC_RADIUS_VOXELS * voxel,
            shape: TrackShape::Tubes,
            color: TracksColor::Direction,
            slab: Some(TRACKS_MOSAIC_SLAB_VOXELS * voxel),
        },
    };
    let mut scenes = mosaic.scenes.clone();
    let mut drawn = 0;
    for scene in &mut scenes {
        let tubes = view_tubes(
            &tracks,
            &scene.regions,
            false,
            &context.volume.voxel_to_world,
        )?;
        drawn += tubes.segments.len();
        scene.peaks = Some(tubes);
        for set in &mut scene.scene.glyph_sets {
            set.scales
                .iter_mut()
                .for_each(|s| *s *= PEAKS_MOSAIC_GLYPH_SIZE);
        }
    }
    let plan = FigurePlan {
        file: "tracks-mosaic.png".into(),
        title: "Tracks mosaic".into(),
        caption: format!(
            "The ODF mosaic's panels with the streamlines of {} ({} of them, {drawn} \
             segments drawn) within half a voxel of each slice, as tubes coloured by their \
             direction in the glyphs' depth buffer; the glyphs at {} times their size in \
             the ODF mosaic.",
            path.display(),
            tractogram.len(),
            PEAKS_MOSAIC_GLYPH_SIZE
        ),
        panels: mosaic.plan.panels.clone(),
        columns: mosaic.plan.columns,
    };
    render(context, renderer, BuiltFigure { plan, scenes })
}

/// Rescales every peak of `scenes` (drawn with half length = amplitude) to
/// `full` times min(1, amplitude / R), with R the [`FULL_LENGTH_PERCENTILE`] of the
/// amplitudes of every peak drawn.
fn size_peaks_alike(scenes: &mut [VolumeScene], full: f64) {
    let mut amplitudes: Vec<f64> = scenes
        .iter()
        .flat_map(|s| s.peaks.iter().flat_map(|p| &p.segments))
        .map(|s| 0.5 * (s.capsule.b - s.capsule.a).length())
        .filter(|a| *a > 0.0)
        .collect();
    if amplitudes.is_empty() {
        return;
    }
    amplitudes.sort_by(f64::total_cmp);
    let reference =
        amplitudes[((amplitudes.len() - 1) as f64 * FULL_LENGTH_PERCENTILE).round() as usize];
    for segment in scenes
        .iter_mut()
        .flat_map(|s| s.peaks.iter_mut().flat_map(|p| &mut p.segments))
    {
        let capsule = &mut segment.capsule;
        let center = 0.5 * (capsule.a + capsule.b);
        let half = 0.5 * (capsule.b - capsule.a);
        let length = half.length();
        if length > 0.0 {
            let scaled = half * (full * (length / reference).min(1.0) / length);
            capsule.a = center - scaled;
            capsule.b = center + scaled;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::{SliceRegion, VolumeReport};
    use glyphcast::scene::{GlyphKind, GlyphSet, Scene};

    /// Peaks of amplitudes 1, 2, 3, 4 (the median 3 by nearest rank) with full length 0.5:
    /// half lengths 1/6, 2/6, then 0.5 for 3 and 4; centres and directions kept.
    #[test]
    fn peaks_are_sized_on_one_scale_up_to_the_median() {
        use glam::DVec3;
        use glyphcast::glyph::capsule::Capsule;
        use glyphcast::render::peaks::{PeakSegment, PeakSet};
        let center = DVec3::new(1.0, 2.0, 3.0);
        let direction = DVec3::new(0.0, 0.6, 0.8);
        let segments = [1.0, 2.0, 3.0, 4.0]
            .map(|a| PeakSegment {
                capsule: Capsule::through(center, a * direction, 0.1),
                color: [1.0; 3],
            })
            .to_vec();
        let region = SliceRegion::new([1, 1, 1], Slice::default(), &VoxelRanges::default(), "v")
            .expect("a region");
        let mut scene = VolumeScene {
            scene: glyphcast::demo::demo_scene(),
            report: VolumeReport::default(),
            region: region.clone(),
            regions: vec![region],
            block: None,
            glyph_radius: 0.0,
            peaks: Some(PeakSet {
                segments,
                lines: Vec::new(),
            }),
        };
        size_peaks_alike(std::slice::from_mut(&mut scene), 0.5);
        let got: Vec<f64> = scene
            .peaks
            .as_ref()
            .unwrap()
            .segments
            .iter()
            .map(|s| {
                let half = 0.5 * (s.capsule.b - s.capsule.a);
                assert!((0.5 * (s.capsule.a + s.capsule.b) - center).length() < 1e-15);
                assert!((half.normalize() - direction).length() < 1e-12);
                half.length()
            })
            .collect();
        let want = [0.5 / 3.0, 1.0 / 3.0, 0.5, 0.5];
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() < 1e-12, "{got:?}");
        }
    }

    /// Per-glyph factors S / r for r = 1, 2, 3, 4 (S = 1): the median radius is 3 by
    /// nearest rank, so the factor is capped at 1/3: radii 1 and 2 are drawn 1/3 and
    /// 2/3, radii 3 and 4 full size.
    #[test]
    fn glyphs_are_sized_on_one_scale_up_to_the_median() {
        let region = SliceRegion::new([1, 1, 1], Slice::default(), &VoxelRanges::default(), "v")
            .expect("a region");
        let set = |scales: Vec<f64>| GlyphSet {
            kind: GlyphKind::Sh {
                band: 0,
                basis: glyphcast::scene::ShBasis::Tournier07,
                legacy: false,
            },
            negative: NegativeMode::Abs,
            shape: Default::default(),
            centers: vec![glam::DVec3::ZERO; scales.len()],
            coeffs: vec![vec![1.0]; scales.len()],
            scales,
        };
        let scene = |scales| VolumeScene {
            scene: Scene {
                glyph_sets: vec![set(scales)],
                camera: glyphcast::demo::demo_scene().camera,
                image: glyphcast::scene::ImageSize {
                    width: 8,
                    height: 8,
                },
            },
            report: VolumeReport::default(),
            region: region.clone(),
            regions: vec![region.clone()],
            block: None,
            glyph_radius: 0.0,
            peaks: None,
        };
        let plan = || FigurePlan {
            file: String::new(),
            title: String::new(),
            caption: String::new(),
            panels: Vec::new(),
            columns: 1,
        };
        let mut figures = vec![
            BuiltFigure {
                plan: plan(),
                scenes: vec![scene(vec![1.0, 0.5])],
            },
            BuiltFigure {
                plan: plan(),
                scenes: vec![scene(vec![1.0 / 3.0, 0.25])],
            },
        ];
        size_alike(&mut figures);
        let scales: Vec<f64> = figures
            .iter()
            .flat_map(|f| &f.scenes[0].scene.glyph_sets[0].scales)
            .copied()
            .collect();
        let expected = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 0.25];
        for (got, want) in scales.iter().zip(expected) {
            assert!((got - want).abs() < 1e-15, "{scales:?}");
        }
    }
}
