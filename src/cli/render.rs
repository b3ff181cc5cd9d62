//! `glyphcast render` and `glyphcast demo`: options, rendering and writing the outputs.
use clap::Args;
use glyphcast::glyph::NegativeMode;
use glyphcast::io::atomic::check_ending;
use glyphcast::render::RenderSettings;
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::render::labels::{draw_edge_labels, edge_labels};
use glyphcast::render::options::{RenderOptions, prepare_render};
use glyphcast::scene::Scene;
use glyphcast::viewer::ViewSource;
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast::volume::ImageRequest;
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
    /// The scene to render; `image` (from --width/--height) sizes a volume's framing.
    pub fn load(&self, image: ImageRequest) -> Result<Scene> {
        match &self.scene {
            Some(path) => self.load_scene_file(path),
            None => self.volume.scene(image),
        }
    }

    /// As [`SceneSource::load`], keeping a volume so that the viewer can move its slice.
    pub fn load_for_view(&self, image: ImageRequest) -> Result<ViewSource> {
        match &self.scene {
            Some(path) => self.load_scene_file(path).map(ViewSource::Scene),
            None => {
                let (volume, options, view) = self.volume.view(image)?;
                Ok(ViewSource::Volume {
                    volume: Box::new(volume),
                    options: Box::new(options),
                    view: Box::new(view),
                })
            }
        }
    }

    fn load_scene_file(&self, path: &Path) -> Result<Scene> {
        if self.volume.is_given() {
            return Err(Error::Usage(
                "give either a scene file or a volume (--sh/--tensor), not both".into(),
            ));
        }
        if let Some(flag) = self.volume.volume_only_flag() {
            return Err(Error::Usage(format!(
                "{flag} applies to volume input (--sh/--tensor), not to a scene file"
            )));
        }
        Scene::load(path)
    }

    /// Whether --labels asks for the anatomical directions at the image's edges.
    pub fn labels(&self) -> bool {
        self.volume.labels
    }

    /// Where --save-scene asks the rendered scene to be written.
    pub fn save_scene(&self) -> Option<&Path> {
        self.volume.save_scene.as_deref()
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
    /// How glyphs are drawn: fixed (ray casting at a fixed step), interval or affine
    /// (robust ray casting by range arithmetic), exact (first real root of the ray
    /// polynomial; offset 0 only), impostor (bounding spheres), mesh:LEVEL (icosphere,
    /// 0 to 7) or latlong:N (N latitude bands) tessellations. Default: exact, or affine
    /// with an --offset (offset glyphs are no polynomial surfaces).
    #[arg(long)]
    method: Option<String>,
    /// Ray caster: fragment (proxy boxes, the default) or compute (a compute shader per
    /// pixel over screen tiles; --method exact only).
    #[arg(long, default_value = "fragment")]
    path: String,
    /// Robust methods: segment length limit, in pixels at the segment's depth.
    #[arg(long, value_name = "PX")]
    precision: Option<f32>,
    /// March step, in units of each glyph's bounding radius.
    #[arg(long)]
    step: Option<f32>,
    /// Refinement of the first sign change: bisect:K, interp or none.
    #[arg(long)]
    refine: Option<String>,
    /// Glyph colour: direction, magnitude, uniform or sign (positive lobes red,
    /// negative ones blue; ray-casting methods only).
    #[arg(long, default_value = "direction")]
    color: String,
    /// Magnitude colormap range LOW:HIGH in world units (default: 0 to the largest glyph
    /// radius drawn, so that the largest glyph's tip takes the map's top colour).
    #[arg(long, value_name = "LOW:HIGH")]
    magnitude_range: Option<String>,
    /// Negative lobes: abs (drawn as |f|) or hide. Sets every glyph set's mode, replacing
    /// a scene file's `negative` (default: the scene's; abs for volumes).
    #[arg(long, value_name = "abs|hide")]
    negative: Option<String>,
    /// Background: none (transparent PNG), dark (the default), black, white, grey,
    /// #rrggbb or r,g,b (sRGB, 0-255, as written in the PNG).
    #[arg(long, value_name = "COLOR")]
    background: Option<String>,
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
    /// --width and --height, checked (`ImageRequest::checked`; a usage error).
    pub fn image_request(&self) -> Result<ImageRequest> {
        ImageRequest::checked(self.width, self.height).map_err(Error::into_usage)
    }

    /// The flags as the library's render options (shared with the Python module).
    pub fn options(&self) -> RenderOptions {
        RenderOptions {
            method: self.method.clone(),
            path: Some(self.path.clone()),
            precision: self.precision,
            step: self.step,
            refine: self.refine.clone(),
            color: Some(self.color.clone()),
            magnitude_range: self.magnitude_range.clone(),
            negative: self.negative.clone(),
            background: self.background.clone(),
            offset: self.offset,
            device: self.device.clone(),
            validation: self.validation,
        }
    }

    /// The render settings of the flags; any error is a usage error (exit 2).
    pub fn settings(&self) -> Result<RenderSettings> {
        self.options().settings().map_err(Error::into_usage)
    }

    /// `--negative`, if given; an unknown mode is a usage error.
    pub fn negative(&self) -> Result<Option<NegativeMode>> {
        self.options().negative().map_err(Error::into_usage)
    }

    pub fn gpu_options(&self) -> GpuOptions {
        self.options().gpu_options()
    }
}

/// Checks every output path of a render before any work (`io::atomic::check_outputs`),
/// and that each name's ending says what it gets (PNG, NumPy, JSON).
pub fn check_outputs(output: &OutputArgs, save_scene: Option<&Path>) -> Result<()> {
    let mut paths: Vec<&Path> = vec![&output.output];
    paths.extend(output.depth_out.as_deref());
    paths.extend(save_scene);
    glyphcast::io::atomic::check_outputs(&paths)?;
    check_ending(&output.output, "-o/--output", &[".png"])?;
    if let Some(depth) = &output.depth_out {
        check_ending(depth, "--depth-out", &[".npy"])?;
    }
    if let Some(scene) = save_scene {
        check_ending(scene, "--save-scene", &[".json"])?;
    }
    Ok(())
}

/// Renders `scene` and writes the outputs (checked first with [`check_outputs`]);
/// `save_scene` receives the scene as rendered (image size included), written with the
/// image and the depth map, all or nothing. `labels` writes the anatomical directions at
/// the image's edges (`render::labels`; volume input only).
pub fn render(
    mut scene: Scene,
    output: &OutputArgs,
    options: &RenderArgs,
    save_scene: Option<&Path>,
    labels: bool,
) -> Result<()> {
    let image = options.image_request()?;
    scene.image.width = image.width.unwrap_or(scene.image.width);
    scene.image.height = image.height.unwrap_or(scene.image.height);
    let settings = options.settings()?;
    let negative = options.negative()?;
    // Written with the image and the depth map, all or nothing.
    let scene_file = save_scene.map(|path| (path, scene.to_json()));
    let started = Instant::now();
    let prepared = prepare_render(scene, settings, negative)?;
    let prepare_time = started.elapsed();
    let gpu = Gpu::headless(&options.gpu_options())?;
    eprintln!("device: {}", gpu.info);
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    let begun = Instant::now();
    let (w, h) = (prepared.width, prepared.height);
    let mut image = renderer.render(&gpu, &prepared.sets, &prepared.camera, w, h, &settings)?;
    if labels {
        let edges = edge_labels(&prepared.camera);
        draw_edge_labels(&mut image.rgba, w, h, &edges)?;
    }
    let glyphs = prepared.glyph_count();
    let gpu_time = image
        .gpu_ms
        .map_or_else(|| "n/a".to_owned(), |ms| format!("{ms:.1} ms"));
    eprintln!(
        "rendered {glyphs} glyphs at {w}x{h}: prepare {:.1} ms, render {:.1} ms (GPU {gpu_time})",
        prepare_time.as_secs_f64() * 1e3,
        begun.elapsed().as_secs_f64() * 1e3
    );
    if let Some(mesh) = &image.mesh {
        eprintln!(
            "{}: {} triangles ({} per glyph), generated in {:.1} ms, {:.1} MiB on the GPU",
            mesh.kind,
            mesh.triangles(),
            mesh.triangles_per_glyph,
            mesh.generate_ms,
            mesh.gpu_bytes() as f64 / (1024.0 * 1024.0)
        );
    }
    write_outputs(&image, output, scene_file)
}

/// Writes the PNG, the depth map and the scene file together: either all are new or all
/// are as they were (`io::atomic::write_all_atomic`).
fn write_outputs(
    image: &RenderedImage,
    output: &OutputArgs,
    scene_file: Option<(&Path, String)>,
) -> Result<()> {
    let (w, h) = (image.width, image.height);
    let png = glyphcast::io::png::encode_png_rgba8(&output.output, w, h, &image.rgba)?;
    let mut files: Vec<(&Path, Vec<u8>)> = vec![(&output.output, png)];
    if let Some(depth) = &output.depth_out {
        let npy = glyphcast::io::npy::encode_depth_npy(depth, w, h, &image.distance)?;
        files.push((depth, npy));
    }
    if let Some((path, json)) = scene_file {
        files.push((path, json.into_bytes()));
    }
    let set: Vec<(&Path, &[u8])> = files.iter().map(|(p, b)| (*p, b.as_slice())).collect();
    glyphcast::io::atomic::write_all_atomic(&set)?;
    eprintln!("wrote {}", output.output.display());
    Ok(())
}
