//! `glyphcast bench`: GPU timings of the glyph pass on a scene, a generated workload, or
//! a sweep, written as a table (stdout) and as CSV and JSON (`--out DIR`).
use clap::Args;
use glyphcast::bench::{self, BenchFrames, BenchResult, workload};
use glyphcast::io::scene::Scene;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::{Refinement, RenderSettings};
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast::{Error, Result};
use std::path::PathBuf;

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file to measure (default: the --workload).
    #[arg(value_name = "SCENE")]
    scene: Option<PathBuf>,
    /// Generated workload: grid:COUNT:ORDER.
    #[arg(long, default_value = "grid:100:8")]
    workload: String,
    /// A sweep instead of one measurement: steps (the seed's Table 1) or scaling
    /// (glyph count, order, resolution).
    #[arg(long)]
    sweep: Option<String>,
    /// Measured frames (after the warm-up).
    #[arg(long, default_value_t = 20)]
    frames: usize,
    /// Warm-up frames, not measured.
    #[arg(long, default_value_t = 3)]
    warmup: usize,
    /// Image width and height (workloads; a scene keeps its own size unless given).
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
    /// Small sweeps and few frames: a check that finishes in a few minutes on lavapipe.
    #[arg(long)]
    quick: bool,
    /// Folder for results.csv, results.json and results.md.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Vulkan device: part of its name or its index.
    #[arg(long)]
    device: Option<String>,
}

impl BenchArgs {
    fn frames(&self) -> BenchFrames {
        if self.quick {
            BenchFrames {
                warmup: 1,
                measured: 3,
            }
        } else {
            BenchFrames {
                warmup: self.warmup,
                measured: self.frames.max(1),
            }
        }
    }

    fn size(&self, default: u32) -> (u32, u32) {
        (
            self.width.unwrap_or(default),
            self.height.unwrap_or(default),
        )
    }

    fn base_scene(&self) -> Result<Scene> {
        match &self.scene {
            Some(path) => {
                let mut scene = Scene::load(path)?;
                scene.image.width = self.width.unwrap_or(scene.image.width);
                scene.image.height = self.height.unwrap_or(scene.image.height);
                Ok(scene)
            }
            None => {
                let (w, h) = self.size(if self.quick { 256 } else { 512 });
                workload::parse(&self.workload, w, h)
            }
        }
    }
}

/// The configurations of a run: (label, scene, settings).
fn configurations(args: &BenchArgs) -> Result<Vec<(String, Scene, RenderSettings)>> {
    let defaults = RenderSettings::default();
    match args.sweep.as_deref() {
        None => Ok(vec![("default".into(), args.base_scene()?, defaults)]),
        Some("steps") => {
            let scene = args.base_scene()?;
            let steps: &[f32] = if args.quick {
                &[0.02, 0.1]
            } else {
                &[0.01, 0.02, 0.05, 0.1, 0.2]
            };
            let refinements = [
                "none", "bisect:1", "bisect:2", "bisect:3", "interp", "secant:4",
            ];
            let mut out = Vec::new();
            for &step in steps {
                for r in refinements {
                    let refinement = r.parse::<Refinement>()?;
                    for (centre, factor) in [("centre", 1.0 / 3.0), ("uniform", 1.0)] {
                        let settings = RenderSettings {
                            step,
                            refinement,
                            centre_step_factor: factor,
                            ..defaults
                        };
                        out.push((format!("step {step} {r} {centre}"), scene.clone(), settings));
                    }
                }
            }
            Ok(out)
        }
        Some("scaling") => {
            let (counts, orders, sizes): (&[usize], &[u32], &[u32]) = if args.quick {
                (&[16, 100], &[2, 8], &[128, 256])
            } else {
                (
                    &[100, 1000, 10_000, 100_000],
                    &[2, 4, 6, 8, 10, 12],
                    &[512, 1024, 2048],
                )
            };
            let mut out = Vec::new();
            for &n in counts {
                out.push((
                    format!("glyphs {n} (order 8)"),
                    workload::grid(n, 8, sizes[0], sizes[0])?,
                    defaults,
                ));
            }
            for &order in orders {
                out.push((
                    format!("order {order} (100 glyphs)"),
                    workload::grid(100, order, sizes[0], sizes[0])?,
                    defaults,
                ));
            }
            for &size in sizes {
                out.push((
                    format!("{size}^2 (100 glyphs, order 8)"),
                    workload::grid(100, 8, size, size)?,
                    defaults,
                ));
            }
            Ok(out)
        }
        Some(other) => Err(Error::Invalid(format!(
            "--sweep: '{other}' is not one of steps, scaling"
        ))),
    }
}

pub fn run(args: &BenchArgs) -> Result<()> {
    let configurations = configurations(args)?;
    let mut options = GpuOptions::from_env();
    if args.device.is_some() {
        options.device = args.device.clone();
    }
    let gpu = Gpu::headless(&options)?;
    eprintln!("device: {}", gpu.info);
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    let progress = super::progress::bar(configurations.len() as u64, "bench");
    let mut results: Vec<BenchResult> = Vec::new();
    for (label, scene, settings) in &configurations {
        progress.set_message(label.clone());
        results.push(bench::run(
            &gpu,
            &mut renderer,
            label,
            scene,
            settings,
            args.frames(),
        )?);
        progress.inc(1);
    }
    progress.finish_and_clear();
    let table = format!("Device: {}\n\n{}", gpu.info, bench::markdown(&results));
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let json = serde_json::json!({ "device": gpu.info.to_string(), "results": results });
        let json =
            serde_json::to_string_pretty(&json).map_err(|e| Error::Invalid(e.to_string()))?;
        glyphcast::io::atomic::write_atomic(&dir.join("results.json"), json.as_bytes())?;
        glyphcast::io::atomic::write_atomic(
            &dir.join("results.csv"),
            bench::csv(&results).as_bytes(),
        )?;
        glyphcast::io::atomic::write_atomic(&dir.join("results.md"), table.as_bytes())?;
    }
    print!("{table}");
    Ok(())
}
