//! Benchmarks: GPU time of the glyph pass from timestamp queries (warm-up frames, then N
//! measured frames; median, min, max), CPU time of preparation, mesh generation and
//! upload, rays and glyphs per second, the GPU memory that coefficients, instances and
//! meshes take, and optionally the accuracy of the frame against the float64 reference
//! (holes, depth error, geometric error in pixels), so that the ray caster, the sphere
//! impostor and tessellations compare in one table. [`ratios`] condenses such tables.
//! Timings are reports for a person to read, never test assertions.
pub mod ratios;
pub mod tables;
pub mod workload;

use crate::Result;
use crate::accuracy::{GeometricError, compare_depth, geometric_error};
use crate::camera::Camera;
use crate::glyph::intersect::WorldGlyph;
use crate::glyph::reference::reference_depth;
use crate::render::glyph_data::{GlyphSetData, WorldGlyphs, prepare_scene, prepare_scene_with};
use crate::render::headless::{HeadlessRenderer, RenderedImage};
use crate::render::{RenderPath, RenderSettings};
use crate::scene::Scene;
use crate::vk::Gpu;
use std::time::Instant;

pub use tables::{csv, markdown};

/// How many frames to draw.
#[derive(Clone, Copy, Debug)]
pub struct BenchFrames {
    /// Frames drawn first and not timed.
    pub warmup: usize,
    /// Frames timed; the result gives their median, min and max.
    pub measured: usize,
}

/// The measurements of one configuration.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchResult {
    /// The configuration's label in tables.
    pub label: String,
    /// The scene measured (configurations of one scene share it), for [`ratios`].
    pub scene: String,
    /// `--method` as spelled on the command line, with " (compute)" where the compute ray
    /// caster drew it.
    pub method: String,
    /// The ray caster that drew it: fragment or compute, as "auto: fragment" or "auto:
    /// compute" where `--path auto` chose it.
    pub path: String,
    /// Glyphs drawn.
    pub glyphs: usize,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// CPU time to turn the scene into GPU data (bounds, normalisation), ms.
    pub prepare_ms: f64,
    /// CPU time of upload and target creation, ms (mesh generation not included).
    pub upload_ms: f64,
    /// Wall-clock time of the CPU mesh generation (parallel), ms; meshes only.
    pub generate_ms: Option<f64>,
    /// Triangles per frame; meshes only.
    pub triangles: Option<usize>,
    /// Mesh vertices and the shared index buffer, bytes; meshes only.
    pub mesh_bytes: Option<usize>,
    /// Median GPU time of the glyph pass over the measured frames, ms.
    pub gpu_ms_median: f64,
    /// Shortest of those times, ms.
    pub gpu_ms_min: f64,
    /// Longest of those times, ms.
    pub gpu_ms_max: f64,
    /// Pixels with a glyph hit: one ray each that found a surface.
    pub covered_pixels: usize,
    /// Covered pixels per second of median GPU time.
    pub rays_per_second: f64,
    /// Glyphs per second of median GPU time.
    pub glyphs_per_second: f64,
    /// GPU bytes of glyph coefficients (0 for meshes).
    pub coefficient_bytes: usize,
    /// GPU bytes of per-glyph instance data (and, for the ray caster, its boxes).
    pub instance_bytes: usize,
    /// GPU bytes of glyph data per glyph: coefficients, instance and mesh (with its share
    /// of the index buffer).
    pub bytes_per_glyph: f64,
    /// Draw calls per frame.
    pub draws: usize,
    /// Passes the glyphs were drawn in (render::visibility).
    pub passes: usize,
    /// How hidden glyphs were skipped: passes, early-out or off (render::visibility).
    pub culling: String,
    /// The `cull` asked for: occluded, passes, early-out or off.
    pub cull_asked: String,
    /// What was asked and what was done, with the reason where culling was asked and
    /// none was done ([`RenderedImage::culling_report`](crate::RenderedImage::culling_report)): `occluded: none needed (1 pass)`.
    pub culling_report: String,
    /// The work of one more frame drawn with the counters on (ray-casting methods on the
    /// fragment path), after the timed ones.
    pub work: Option<crate::render::visibility::WorkCounts>,
    /// Against the float64 reference, when one was given.
    pub accuracy: Option<BenchAccuracy>,
    /// Tube segments drawn with the glyphs (capsules of a tracks workload), 0 if none.
    pub tube_segments: usize,
    /// Their bytes on the GPU (each capsule's instance: ends, radius, colour).
    pub tube_bytes: usize,
}

/// How a benchmarked frame compares with the float64 reference.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct BenchAccuracy {
    /// Away from the one-pixel silhouette band (see `accuracy::compare_depth`).
    pub holes: usize,
    /// Pixels drawn where the reference has no glyph, away from the same band.
    pub false_hits: usize,
    /// Depth errors along the rays, in units of the largest glyph's bounding radius.
    pub median_depth_error: f64,
    /// 99th percentile of the same depth errors.
    pub p99_depth_error: f64,
    /// Surface distance and coverage errors.
    pub geometric: GeometricError,
    /// `geometric.pixels()`: the larger of the surface and silhouette errors, pixels.
    pub error_px: f64,
}

/// The float64 reference of a scene: computed once, held against every configuration.
pub struct Reference {
    /// Ray distance per pixel, row-major; NaN where no glyph is hit.
    pub depth: Vec<f64>,
    /// The scene's glyphs placed in the world.
    pub glyphs: Vec<WorldGlyph>,
    /// The largest world bounding radius: depth errors are in its units.
    pub scale: f64,
}

impl Reference {
    /// The reference of `scene` drawn without offset (as every sweep draws it).
    pub fn of(scene: &Scene) -> Result<Reference> {
        let sets = prepare_scene(scene, 0.0)?;
        let glyphs: Vec<WorldGlyph> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
        let (w, h) = (scene.image.width, scene.image.height);
        let depth = reference_depth(&glyphs, &scene.camera, w, h);
        let scale = glyphs
            .iter()
            .map(WorldGlyph::world_radius)
            .fold(0.0, f64::max);
        Ok(Reference {
            depth,
            glyphs,
            scale,
        })
    }

    fn compare(&self, image: &RenderedImage, camera: &Camera) -> BenchAccuracy {
        let (w, h) = (image.width, image.height);
        let depth = compare_depth(
            &image.distance,
            &self.depth,
            w as usize,
            h as usize,
            self.scale,
        );
        let geometric = geometric_error(&image.distance, &self.depth, &self.glyphs, camera, w, h);
        BenchAccuracy {
            holes: depth.holes,
            false_hits: depth.false_hits,
            median_depth_error: depth.median_error,
            p99_depth_error: depth.p99_error,
            geometric,
            error_px: geometric.pixels(),
        }
    }
}

/// What to measure: a scene (named, for [`ratios`]) with settings, under a label.
pub struct BenchCase<'a> {
    /// The configuration's label in tables.
    pub label: &'a str,
    /// The scene's name, copied into [`BenchResult::scene`].
    pub scene_name: &'a str,
    /// The scene to draw.
    pub scene: &'a Scene,
    /// How to draw it.
    pub settings: &'a RenderSettings,
    /// The scene's reference (drawn without offset), to measure accuracy against.
    pub reference: Option<&'a Reference>,
    /// Tubes drawn with the glyphs (a tracks workload), if any.
    pub tubes: Option<&'a crate::render::peaks::PeakSet>,
}

/// Measures one case. Errors if the device has no timestamps.
pub fn run(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    case: &BenchCase,
    frames: BenchFrames,
) -> Result<BenchResult> {
    let started = Instant::now();
    // Only the mesh pass draws from the float64 glyphs (the reference has its own).
    let pieces = case.settings.proxy == crate::render::Proxy::Pieces;
    let world = match case.settings.method {
        crate::render::Method::Mesh(_) => WorldGlyphs::Keep,
        _ if pieces => WorldGlyphs::Keep,
        _ => WorldGlyphs::Leave,
    };
    let mut sets = prepare_scene_with(case.scene, case.settings.offset as f64, world)?;
    if pieces {
        crate::render::glyph_data::add_pieces(&mut sets)?;
        if !matches!(case.settings.method, crate::render::Method::Mesh(_)) {
            sets.iter_mut().for_each(|s| s.drop_reference_glyphs());
        }
    }
    let prepare_ms = started.elapsed().as_secs_f64() * 1e3;
    let mut result = measure_prepared(gpu, renderer, case, sets, frames, prepare_ms)?;
    result.scene = case.scene_name.to_owned();
    Ok(result)
}

fn measure_prepared(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    case: &BenchCase,
    sets: Vec<GlyphSetData>,
    frames: BenchFrames,
    prepare_ms: f64,
) -> Result<BenchResult> {
    let (camera, settings) = (&case.scene.camera, case.settings);
    let (width, height) = (case.scene.image.width, case.scene.image.height);
    let glyphs: usize = sets.iter().map(GlyphSetData::len).sum();
    let set_bytes = (
        sets.iter().map(|s| 4 * s.coefficients.len()).sum(),
        sets.iter()
            .map(|s| 16 * s.instances.len() + 32 * s.boxes.len())
            .sum(),
    );
    let started = Instant::now();
    let mut frame = renderer.prepare_view(
        gpu,
        &sets,
        &crate::render::headless::FrameView::new(camera, width, height).with_peaks(case.tubes),
        settings,
    )?;
    // The GPU holds its own copy now (a million band-8 glyphs: 230 MB less at the
    // process's peak, which the frame's own memory on a software device would raise).
    drop(sets);
    let mesh = frame.mesh_stats().copied();
    let generate_ms = mesh.map(|m| m.generate_ms);
    let upload_ms = started.elapsed().as_secs_f64() * 1e3 - generate_ms.unwrap_or(0.0);
    for _ in 0..frames.warmup {
        renderer.draw(gpu, &frame)?;
    }
    let mut times = Vec::with_capacity(frames.measured);
    for _ in 0..frames.measured.max(1) {
        let ms = renderer.draw(gpu, &frame)?.ok_or(crate::Error::Setup {
            missing: "timestamps from this device's queue, which GPU times need",
            found: None,
        })?;
        times.push(ms);
    }
    let image = renderer.read(gpu, &frame)?;
    // The work, counted in a frame of its own: the counters' atomics are not timed.
    frame.count_work(true);
    renderer.draw(gpu, &frame)?;
    // The counters are the ray-casting pass's: the impostor, the meshes and the compute
    // path count nothing, and their zeros would read as work saved.
    let counted = frame.path() == RenderPath::Fragment
        && !matches!(
            settings.method,
            crate::render::Method::Impostor | crate::render::Method::Mesh(_)
        );
    let work = frame.work()?.filter(|_| counted);
    frame.count_work(false);
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let covered = image.distance.iter().filter(|d| !d.is_nan()).count();
    let (coefficient_bytes, instance_bytes, mesh_bytes) = match &mesh {
        Some(m) => (0, m.instance_bytes, Some(m.vertex_bytes + m.index_bytes)),
        None => (set_bytes.0, set_bytes.1, None),
    };
    let total_bytes = coefficient_bytes + instance_bytes + mesh_bytes.unwrap_or(0);
    Ok(BenchResult {
        label: case.label.to_owned(),
        scene: String::new(),
        method: match frame.path() {
            RenderPath::Compute => format!("{} (compute)", settings.method),
            _ => settings.method.to_string(),
        },
        path: match settings.path {
            RenderPath::Auto => format!("auto: {}", frame.path()),
            _ => frame.path().to_string(),
        },
        glyphs,
        width,
        height,
        prepare_ms,
        upload_ms,
        generate_ms,
        triangles: mesh.map(|m| m.triangles()),
        mesh_bytes,
        gpu_ms_median: median,
        gpu_ms_min: times[0],
        gpu_ms_max: times[times.len() - 1],
        covered_pixels: covered,
        rays_per_second: covered as f64 / (median * 1e-3),
        glyphs_per_second: glyphs as f64 / (median * 1e-3),
        coefficient_bytes,
        instance_bytes,
        bytes_per_glyph: total_bytes as f64 / glyphs.max(1) as f64,
        draws: image.draws,
        passes: frame.passes(),
        culling: frame.culling().to_string(),
        cull_asked: settings.cull.to_string(),
        culling_report: crate::render::culling_report::report(
            gpu.context(),
            settings,
            crate::render::culling_report::Drawn {
                path: frame.path(),
                culling: frame.culling(),
                passes: frame.passes(),
                target: (width, height),
            },
        ),
        work,
        accuracy: case.reference.map(|r| r.compare(&image, camera)),
        tube_segments: case.tubes.map_or(0, |t| t.all().count()),
        tube_bytes: case.tubes.map_or(0, |t| {
            t.all().count() * std::mem::size_of::<crate::render::peaks::CapsuleInstance>()
        }),
    })
}
