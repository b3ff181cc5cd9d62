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
use crate::glyph::NegativeMode;
use crate::io::nifti::AffineSource;
use crate::render::RenderSettings;
use crate::render::compose::montage::prepare_montage;
use crate::render::headless::{HeadlessRenderer, RenderedImage};
use crate::render::underlay::{Underlay, UnderlayVolume};
use crate::vk::Gpu;
use crate::volume::UnderlayPlacement;
use crate::volume::{PeakStyle, PeaksColor, ViewPeaks, load_peaks, peak_set};
use crate::volume::{Slice, SliceAxis, Volume, VolumeOptions, VolumeScene, VoxelRanges};
use crate::volume::{view_underlay, volume_scene};
use crate::{Error, Result};

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
    pub plan: FigurePlan,
    pub scenes: Vec<VolumeScene>,
}

/// A rendered figure.
pub struct Figure {
    pub file: String,
    pub title: String,
    pub caption: String,
    pub panel_captions: Vec<String>,
    pub columns: usize,
    pub image: RenderedImage,
    /// Glyphs drawn in all panels.
    pub glyphs: usize,
}

/// The underlay image shared by every panel, with the source of its affine.
pub struct SharedUnderlay {
    pub volume: Arc<UnderlayVolume>,
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
    pub gpu: &'a Gpu,
    pub settings: RenderSettings,
    pub negative: Option<NegativeMode>,
    pub underlay: Option<&'a SharedUnderlay>,
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
        return Err(Error::Invalid(format!("{}: an empty figure", plan.file)));
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

/// The peaks mosaic: the ODF mosaic's panels (`mosaic`, built and sized with the rest)
/// with the peaks of the image at `peaks` (checked against the ODFs' grid by the
/// caller) drawn over the glyphs in the same depth buffer, as `render --peaks` draws
/// them: capsules through the voxel centres, white so that they stand out from the
/// direction-coloured lobes, lengths proportional to the amplitudes.
pub fn peaks_mosaic(
    context: &DrawContext,
    renderer: &mut HeadlessRenderer,
    mosaic: &BuiltFigure,
    peaks: &Path,
) -> Result<Figure> {
    let view = ViewPeaks {
        volume: Arc::new(load_peaks(peaks, None)?),
        style: PeakStyle {
            color: PeaksColor::Uniform([1.0, 1.0, 1.0]),
            ..PeakStyle::default()
        },
    };
    let mut scenes = mosaic.scenes.clone();
    for scene in &mut scenes {
        let camera = &scene.scene.camera;
        let height = scene.scene.image.height;
        scene.peaks = Some(peak_set(&view, &scene.regions, None, camera, height)?);
    }
    let plan = FigurePlan {
        file: "peaks-mosaic.png".into(),
        title: "Peaks mosaic".into(),
        caption: format!(
            "The ODF mosaic's panels with the peaks of {} drawn over the glyphs (white \
             capsules through the voxel centres, lengths proportional to the amplitudes).",
            peaks.display()
        ),
        panels: mosaic.plan.panels.clone(),
        columns: mosaic.plan.columns,
    };
    render(context, renderer, BuiltFigure { plan, scenes })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{GlyphKind, GlyphSet, Scene};
    use crate::volume::{SliceRegion, VolumeReport};

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
                basis: crate::scene::ShBasis::Tournier07,
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
                camera: crate::demo::demo_scene().camera,
                image: crate::scene::ImageSize {
                    width: 8,
                    height: 8,
                },
            },
            report: VolumeReport::default(),
            region: region.clone(),
            regions: vec![region.clone()],
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
