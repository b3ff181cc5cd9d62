//! Benchmarks: GPU time of the glyph pass from timestamp queries (warm-up frames, then N
//! measured frames; median, min, max), CPU time of preparation and upload, rays and
//! glyphs per second, and the GPU memory that coefficients and instances take.
//! Timings are reports for a person to read, never test assertions.
pub mod workload;

use crate::Result;
use crate::camera::Camera;
use crate::io::scene::Scene;
use crate::render::RenderSettings;
use crate::render::glyph_data::{GlyphSetData, prepare_scene};
use crate::render::headless::HeadlessRenderer;
use crate::vk::Gpu;
use std::time::Instant;

/// How many frames to draw.
#[derive(Clone, Copy, Debug)]
pub struct BenchFrames {
    pub warmup: usize,
    pub measured: usize,
}

/// The measurements of one configuration.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchResult {
    pub label: String,
    pub glyphs: usize,
    pub width: u32,
    pub height: u32,
    /// CPU time to turn the scene into GPU data (bounds, normalisation), ms.
    pub prepare_ms: f64,
    /// CPU time of upload and target creation, ms.
    pub upload_ms: f64,
    pub gpu_ms_median: f64,
    pub gpu_ms_min: f64,
    pub gpu_ms_max: f64,
    /// Pixels with a glyph hit: one ray each that found a surface.
    pub covered_pixels: usize,
    pub rays_per_second: f64,
    pub glyphs_per_second: f64,
    pub coefficient_bytes: usize,
    pub instance_bytes: usize,
    pub draws: usize,
}

/// Measures `scene` with `settings`. Errors if the device has no timestamps.
pub fn run(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    label: &str,
    scene: &Scene,
    settings: &RenderSettings,
    frames: BenchFrames,
) -> Result<BenchResult> {
    let started = Instant::now();
    let sets = prepare_scene(scene, settings.offset as f64)?;
    let prepare_ms = started.elapsed().as_secs_f64() * 1e3;
    measure_prepared(
        gpu,
        renderer,
        label,
        &sets,
        &scene.camera,
        scene.image.width,
        scene.image.height,
        settings,
        frames,
        prepare_ms,
    )
}

#[allow(clippy::too_many_arguments)]
fn measure_prepared(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    label: &str,
    sets: &[GlyphSetData],
    camera: &Camera,
    width: u32,
    height: u32,
    settings: &RenderSettings,
    frames: BenchFrames,
    prepare_ms: f64,
) -> Result<BenchResult> {
    let started = Instant::now();
    let frame = renderer.prepare(gpu, sets, camera, width, height, settings)?;
    let upload_ms = started.elapsed().as_secs_f64() * 1e3;
    for _ in 0..frames.warmup {
        renderer.draw(gpu, &frame)?;
    }
    let mut times = Vec::with_capacity(frames.measured);
    for _ in 0..frames.measured.max(1) {
        let ms = renderer.draw(gpu, &frame)?.ok_or_else(|| {
            crate::Error::Setup(
                "this device's queue writes no timestamps; GPU times are unavailable".into(),
            )
        })?;
        times.push(ms);
    }
    let image = renderer.read(gpu, &frame)?;
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let covered = image.distance.iter().filter(|d| !d.is_nan()).count();
    let glyphs: usize = sets.iter().map(GlyphSetData::len).sum();
    Ok(BenchResult {
        label: label.to_owned(),
        glyphs,
        width,
        height,
        prepare_ms,
        upload_ms,
        gpu_ms_median: median,
        gpu_ms_min: times[0],
        gpu_ms_max: times[times.len() - 1],
        covered_pixels: covered,
        rays_per_second: covered as f64 / (median * 1e-3),
        glyphs_per_second: glyphs as f64 / (median * 1e-3),
        coefficient_bytes: sets.iter().map(|s| 4 * s.coefficients.len()).sum(),
        instance_bytes: sets.iter().map(|s| 16 * s.instances.len()).sum(),
        draws: image.draws,
    })
}

const COLUMNS: [&str; 12] = [
    "label",
    "glyphs",
    "size",
    "GPU ms (median)",
    "min",
    "max",
    "prepare ms",
    "upload ms",
    "Mrays/s",
    "glyphs/s",
    "coeff bytes",
    "instance bytes",
];

/// A readable Markdown table.
pub fn markdown(results: &[BenchResult]) -> String {
    let mut out = format!(
        "| {} |\n|{}\n",
        COLUMNS.join(" | "),
        "---|".repeat(COLUMNS.len())
    );
    for r in results {
        out.push_str(&format!(
            "| {} | {} | {}x{} | {:.3} | {:.3} | {:.3} | {:.1} | {:.1} | {:.2} | {:.0} | {} | {} |\n",
            r.label, r.glyphs, r.width, r.height, r.gpu_ms_median, r.gpu_ms_min, r.gpu_ms_max,
            r.prepare_ms, r.upload_ms, r.rays_per_second * 1e-6, r.glyphs_per_second,
            r.coefficient_bytes, r.instance_bytes
        ));
    }
    out
}

pub fn csv(results: &[BenchResult]) -> String {
    let mut out = String::from(
        "label,glyphs,width,height,gpu_ms_median,gpu_ms_min,gpu_ms_max,prepare_ms,upload_ms,covered_pixels,rays_per_second,glyphs_per_second,coefficient_bytes,instance_bytes,draws\n",
    );
    for r in results {
        out.push_str(&format!(
            "{},{},{},{},{:.6},{:.6},{:.6},{:.3},{:.3},{},{:.1},{:.1},{},{},{}\n",
            r.label,
            r.glyphs,
            r.width,
            r.height,
            r.gpu_ms_median,
            r.gpu_ms_min,
            r.gpu_ms_max,
            r.prepare_ms,
            r.upload_ms,
            r.covered_pixels,
            r.rays_per_second,
            r.glyphs_per_second,
            r.coefficient_bytes,
            r.instance_bytes,
            r.draws
        ));
    }
    out
}
