//! `glyphcast render` and `glyphcast demo`: options, rendering and writing the outputs.
use clap::Args;
use glyphcast::io::scene::Scene;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::render::{ColorMode, Method, Refinement, RenderSettings};
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast::{Error, Result};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where the glyphs come from: a scene file, or a volume (see `cli::volume`).
#[derive(Args)]
pub struct SceneSource {
    /// Scene file (JSON).
    #[arg(value_name = "SCENE", required_unless_present_any = super::volume::VOLUME_FLAGS)]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub volume: super::volume::VolumeArgs,
}

impl SceneSource {
    pub fn load(&self) -> Result<Scene> {
        match &self.scene {
            Some(path) => {
                if self.volume.is_given() {
                    return Err(Error::Invalid(
                        "give either a scene file or a volume (--sh/--tensor), not both".into(),
                    ));
                }
                Scene::load(path)
            }
            None => self.volume.scene(),
        }
    }
}

#[derive(Args)]
pub struct OutputArgs {
    /// Output image (PNG).
    #[arg(
        short = 'o',
        long = "output",
        value_name = "PNG",
        default_value = "glyphcast.png"
    )]
    pub output: PathBuf,
    /// Also write the ray distance per pixel as a float32 .npy (NaN for misses).
    #[arg(long, value_name = "NPY")]
    pub depth_out: Option<PathBuf>,
}

#[derive(Args)]
pub struct RenderArgs {
    /// Image width in pixels (default: the scene's).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long)]
    height: Option<u32>,
    /// Intersection method: fixed (march and refine) or exact (real-root isolation;
    /// offset 0 only).
    #[arg(long, default_value = "fixed")]
    method: String,
    /// March step, in units of each glyph's bounding radius.
    #[arg(long)]
    step: Option<f32>,
    /// Refinement of the first sign change: bisect:K, interp or none.
    #[arg(long)]
    refine: Option<String>,
    /// Glyph colour: direction, magnitude or uniform.
    #[arg(long, default_value = "direction")]
    color: String,
    /// Magnitude colormap range LOW:HIGH in world units (default: 0 to the largest glyph).
    #[arg(long, value_name = "LOW:HIGH")]
    magnitude_range: Option<String>,
    /// Isotropic offset added to every glyph, as a fraction of its bounding radius.
    #[arg(long, default_value_t = 0.0)]
    offset: f32,
    /// Vulkan device: part of its name or its index (also GLYPHCAST_DEVICE).
    #[arg(long)]
    device: Option<String>,
    /// Turn on the Vulkan validation layer (also GLYPHCAST_VALIDATION=1).
    #[arg(long)]
    validation: bool,
}

impl RenderArgs {
    fn settings(&self) -> Result<RenderSettings> {
        let mut s = RenderSettings {
            method: self.method.parse::<Method>()?,
            ..Default::default()
        };
        if let Some(step) = self.step {
            s.step = step;
        }
        if let Some(refine) = &self.refine {
            s.refinement = refine.parse::<Refinement>()?;
        }
        s.color = self.color.parse::<ColorMode>()?;
        if let Some(range) = &self.magnitude_range {
            let parsed = range
                .split_once(':')
                .and_then(|(lo, hi)| Some((lo.parse::<f32>().ok()?, hi.parse::<f32>().ok()?)));
            let Some(pair) = parsed else {
                return Err(Error::Invalid(format!(
                    "--magnitude-range: '{range}' is not LOW:HIGH"
                )));
            };
            s.color = ColorMode::Magnitude { range: Some(pair) };
        }
        s.offset = self.offset;
        s.validate()?;
        Ok(s)
    }

    fn gpu_options(&self) -> GpuOptions {
        let mut options = GpuOptions::from_env();
        options.validation |= self.validation;
        if self.device.is_some() {
            options.device = self.device.clone();
        }
        options
    }
}

pub fn render(mut scene: Scene, output: &OutputArgs, options: &RenderArgs) -> Result<()> {
    for (name, value) in [("--width", options.width), ("--height", options.height)] {
        if let Some(v) = value
            && (v == 0 || v > 16384)
        {
            return Err(Error::Invalid(format!("{name}: {v} must be in 1..=16384")));
        }
    }
    scene.image.width = options.width.unwrap_or(scene.image.width);
    scene.image.height = options.height.unwrap_or(scene.image.height);
    let settings = options.settings()?;
    let started = Instant::now();
    let sets = prepare_scene(&scene, settings.offset as f64)?;
    let prepared = started.elapsed();
    let gpu = Gpu::headless(&options.gpu_options())?;
    eprintln!("device: {}", gpu.info);
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    let begun = Instant::now();
    let (w, h) = (scene.image.width, scene.image.height);
    let image = renderer.render(&gpu, &sets, &scene.camera, w, h, &settings)?;
    let glyphs: usize = sets.iter().map(|s| s.len()).sum();
    eprintln!(
        "rendered {glyphs} glyphs at {w}x{h}: prepare {:.1} ms, render {:.1} ms",
        prepared.as_secs_f64() * 1e3,
        begun.elapsed().as_secs_f64() * 1e3
    );
    write_outputs(&image, output)
}

/// Writes the PNG and the depth map; if the second write fails, the first is removed so
/// that no partial output stays behind.
fn write_outputs(image: &RenderedImage, output: &OutputArgs) -> Result<()> {
    glyphcast::io::png::write_png_rgba8(&output.output, image.width, image.height, &image.rgba)?;
    if let Some(depth) = &output.depth_out {
        let written =
            glyphcast::io::npy::write_depth_npy(depth, image.width, image.height, &image.distance);
        if let Err(e) = written {
            remove_quietly(&output.output);
            return Err(e);
        }
    }
    eprintln!("wrote {}", output.output.display());
    Ok(())
}

fn remove_quietly(path: &Path) {
    let _ = std::fs::remove_file(path);
}
