//! `glyphcast render` and `glyphcast demo`: options, rendering and writing the outputs.
use clap::Args;
use glyphcast::error::Relation;
use glyphcast::glyph::NegativeMode;
use glyphcast::io::atomic::check_ending;
use glyphcast::render::ColorMode;
use glyphcast::render::RenderSettings;
use glyphcast::render::compose::colorbar::common_scale;
use glyphcast::render::compose::figure::{ColorBarRequest, Overlays, finish_figure, render_figure};
use glyphcast::render::compose::montage::prepare_montage;
use glyphcast::render::headless::{FrameView, HeadlessRenderer, RenderedImage};
use glyphcast::render::options::{RenderOptions, prepare_render};
use glyphcast::render::peaks::PeakSet;
use glyphcast::render::promote::early_variants;
use glyphcast::render::underlay::Underlay;
use glyphcast::scene::Scene;
use glyphcast::vk::{Gpu, GpuOptions};
use glyphcast::{Error, Result, Setting};
use glyphcast_dmri::volume::{ImageRequest, VolumeFigure, VolumeMontage, VolumeView};
use glyphcast_viewer::ViewSource;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where the glyphs come from: a scene file, or a volume (see `cli::volume`).
#[derive(Args)]
pub struct SceneSource {
    /// Scene file (JSON); without it, a volume (--sh, --tensor or --peaks).
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub volume: super::volume::VolumeArgs,
}

/// What `render` draws: a scene (a scene file's, or a volume's view with its underlay)
/// or the panels of a montage.
pub enum Loaded {
    /// One scene, with the volume's underlay and peaks if any.
    Scene(Scene, Option<Underlay>, Option<PeakSet>),
    /// The panels of `--views` or `--lightbox`.
    Montage(VolumeMontage),
}

impl SceneSource {
    /// Refuses a request with neither a scene file nor a volume, before any file is
    /// read: a volume-only flag given alone (`--block`) is told that it needs a volume,
    /// not a scene file (a usage error).
    pub fn check(&self) -> Result<()> {
        if self.scene.is_some() || self.volume.is_given() {
            return Ok(());
        }
        Err(match self.volume.volume_only_flag() {
            Some(flag) => Error::conflict(
                flag,
                Relation::Requires,
                "a volume to draw: --sh FILE or --tensor FILE (or --peaks FILE)",
            ),
            None => Error::conflict(
                "drawing",
                Relation::Requires,
                "a scene file (SCENE) or a volume: --sh FILE, --tensor FILE or --peaks FILE",
            ),
        })
    }

    /// What to render; `image` (from --width/--height) sizes a volume's framing.
    pub fn load(&self, image: ImageRequest) -> Result<Loaded> {
        if let Some(path) = &self.scene {
            return Ok(Loaded::Scene(self.load_scene_file(path)?, None, None));
        }
        Ok(match self.volume.figure(image)? {
            VolumeFigure::View(view) => {
                Loaded::Scene(view.scene.scene, view.underlay, view.scene.peaks)
            }
            VolumeFigure::Montage(montage) => Loaded::Montage(montage),
        })
    }

    /// The scene to view, keeping a volume so that the viewer can move its slice (and
    /// the underlay with it).
    pub fn load_for_view(&self, image: ImageRequest) -> Result<(ViewSource, Option<Underlay>)> {
        if let Some(path) = &self.scene {
            return Ok((ViewSource::Scene(self.load_scene_file(path)?), None));
        }
        if self.volume.is_montage() {
            return Err(Error::conflict(
                "--views/--lightbox",
                Relation::Requires,
                "render (they make one image of several panels)",
            ));
        }
        match self.volume.figure(image)? {
            VolumeFigure::View(view) => {
                let VolumeView {
                    volume,
                    options,
                    scene,
                    underlay,
                    ..
                } = *view;
                let source = ViewSource::Volume {
                    volume: Box::new(volume),
                    options: Box::new(options),
                    view: Box::new(scene),
                };
                Ok((source, underlay))
            }
            VolumeFigure::Montage(_) => Err(Error::Call {
                call: "SceneSource::load_for_view",
                expected: "one view, not a montage",
            }),
        }
    }

    fn load_scene_file(&self, path: &Path) -> Result<Scene> {
        if self.volume.is_given() {
            return Err(Error::conflict(
                "a scene file",
                Relation::Exclusive,
                "a volume (--sh/--tensor)",
            ));
        }
        if let Some(flag) = self.volume.volume_only_flag() {
            return Err(Error::conflict(
                flag,
                Relation::Excludes,
                "a scene file (it applies to volume input, --sh/--tensor)",
            ));
        }
        let mut scene = Scene::load(path)?;
        self.volume.apply_shape(&mut scene)?;
        Ok(scene)
    }

    /// Whether --labels asks for the anatomical directions at the image's edges.
    pub fn labels(&self) -> bool {
        self.volume.labels
    }

    /// Every file the render reads: the scene file and its arrays, or the volume's
    /// images (coefficients, mask, underlay, peaks).
    pub fn input_paths(&self) -> Vec<PathBuf> {
        let mut paths: Vec<PathBuf> = Vec::new();
        if let Some(scene) = &self.scene {
            paths.push(scene.clone());
            paths.extend(glyphcast::scene::Scene::array_files(scene));
        }
        paths.extend(self.volume.input_paths().into_iter().map(Path::to_path_buf));
        paths
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
    /// The print resolution recorded in the PNG (its pHYs chunk), in pixels per inch:
    /// a layout program then places the image at width / DPI inches.
    #[arg(long, value_name = "DPI")]
    pub dpi: Option<f64>,
}

impl OutputArgs {
    /// Checks the output options' values (`--dpi`) before any work.
    pub fn check(&self) -> Result<()> {
        self.dpi().map(|_| ())
    }

    /// `--dpi`, checked: a finite number above 0 (a usage error otherwise).
    fn dpi(&self) -> Result<Option<f64>> {
        match self.dpi {
            Some(dpi) if !(dpi.is_finite() && dpi > 0.0 && dpi <= 1e6) => Err(
                Error::setting_value(Setting::Dpi, dpi, "must be above 0 (at most 1000000)"),
            ),
            dpi => Ok(dpi),
        }
    }
}

#[derive(Args)]
pub struct RenderArgs {
    /// Image width in pixels (default: the scene's).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's).
    #[arg(long)]
    height: Option<u32>,
    /// Multiply the image's width and height by F, keeping its framing: the same figure
    /// with more pixels (labels, captions and the colour bar grow with it).
    #[arg(long, value_name = "F")]
    scale_factor: Option<f64>,
    /// The render settings (method, colour, lighting, ...): the library's table.
    #[command(flatten)]
    settings: super::setting_flags::SettingFlags,
    /// With --color magnitude: append a colour bar of the magnitude range on the right,
    /// in a strip of its own (the PNG and the depth map grow by its width; the depth map
    /// is NaN there). Values are glyph radii in data units (|f|, or an ellipsoid's
    /// sqrt(eigenvalue)) when every glyph has the same scale, else in world units.
    #[arg(long)]
    colorbar: bool,
    /// The colour bar's label (default: "radius (data units)" or "radius (world units)").
    #[arg(long, value_name = "TEXT", requires = "colorbar")]
    colorbar_label: Option<String>,
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
        ImageRequest::checked(self.width, self.height)
    }

    /// `width` x `height` times `--scale-factor`, rounded: the size of an image of the
    /// same framing. A factor that is not above 0, or a side beyond the largest image,
    /// is a usage error.
    pub fn scaled(&self, width: u32, height: u32) -> Result<(u32, u32)> {
        let Some(factor) = self.scale_factor else {
            return Ok((width, height));
        };
        let max = glyphcast::scene::MAX_IMAGE_SIDE;
        let side = |n: u32| (f64::from(n) * factor).round();
        let (w, h) = (side(width), side(height));
        if !(factor.is_finite() && factor > 0.0) {
            return Err(Error::setting_value(
                Setting::ScaleFactor,
                factor,
                "must be above 0",
            ));
        }
        if !(1.0..=f64::from(max)).contains(&w) || !(1.0..=f64::from(max)).contains(&h) {
            return Err(Error::setting_value(
                Setting::ScaleFactor,
                factor,
                format!("makes the {width} x {height} image {w} x {h}: each side 1 to {max}"),
            ));
        }
        Ok((w as u32, h as u32))
    }

    /// The flags as the library's render options (the Python module's too); a bad
    /// value is a usage error naming its flag.
    pub fn options(&self) -> Result<RenderOptions> {
        self.settings.options()
    }

    /// The render settings of the flags; any error is a usage error (exit 2).
    pub fn settings(&self) -> Result<RenderSettings> {
        self.options()?.settings()
    }

    /// Checks every option value of a one-shot image before any file is read: the
    /// size, each setting's value, the settings the method (and the colour bar, and
    /// `--cull`) need or do not read. Returns the settings.
    pub fn check(&self) -> Result<RenderSettings> {
        self.image_request()?;
        let settings = self.settings()?;
        self.check_colorbar(&settings)?;
        self.options()?.check_method_reads(&settings)?;
        Ok(settings)
    }

    /// Whether `--colorbar` was given.
    pub fn wants_colorbar(&self) -> bool {
        self.colorbar
    }

    /// Checks that `--colorbar` goes with `--color magnitude` (a usage error otherwise).
    pub fn check_colorbar(&self, settings: &RenderSettings) -> Result<()> {
        if self.colorbar && !matches!(settings.color, ColorMode::Magnitude { .. }) {
            return Err(Error::setting(
                Setting::Colorbar,
                glyphcast::message![
                    "shows the magnitude colour map: it needs ",
                    Setting::Color.with("magnitude"),
                    ", not ",
                    Setting::Color.with(settings.color)
                ],
            ));
        }
        Ok(())
    }

    /// `--colorbar-label`, if given.
    pub fn colorbar_label(&self) -> Option<&str> {
        self.colorbar_label.as_deref()
    }

    /// The colour bar asked for, if `--colorbar`: `common_scale` is the one scale of
    /// every glyph, if they share one (values are then divided by it: data units).
    fn colorbar_request(&self, common_scale: Option<f64>) -> Option<ColorBarRequest<'_>> {
        self.colorbar.then(|| ColorBarRequest {
            label: self.colorbar_label(),
            common_scale,
        })
    }

    /// `--negative`, if given; an unknown mode is a usage error.
    pub fn negative(&self) -> Result<Option<NegativeMode>> {
        Ok(self.options()?.negative)
    }

    /// The device options: the environment's (GLYPHCAST_VALIDATION, GLYPHCAST_DEVICE),
    /// with `--validation` and `--device` on top.
    pub fn gpu_options(&self) -> GpuOptions {
        GpuOptions::from_env().with(self.device.clone(), self.validation)
    }
}

/// Checks every output path of a render before any work (`io::atomic::check_outputs`:
/// none may be one of the `inputs`), and that each name's ending says what it gets
/// (PNG, NumPy, JSON).
pub fn check_outputs(
    output: &OutputArgs,
    save_scene: Option<&Path>,
    inputs: &[PathBuf],
) -> Result<()> {
    let mut paths: Vec<&Path> = vec![&output.output];
    paths.extend(output.depth_out.as_deref());
    paths.extend(save_scene);
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    glyphcast::io::atomic::check_outputs(&paths, &inputs)?;
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
/// the image's edges (`render::compose::labels`; volume input only); `underlay` and `peaks` are
/// drawn in the glyphs' depth buffer (volume input only).
pub fn render(
    mut scene: Scene,
    output: &OutputArgs,
    options: &RenderArgs,
    save_scene: Option<&Path>,
    labels: bool,
    underlay: Option<&Underlay>,
    peaks: Option<&PeakSet>,
) -> Result<()> {
    let image = options.image_request()?;
    (scene.image.width, scene.image.height) = options.scaled(
        image.width.unwrap_or(scene.image.width),
        image.height.unwrap_or(scene.image.height),
    )?;
    output.dpi()?;
    let settings = options.check()?;
    settings.check_shapes(scene.glyph_sets.iter().map(|s| s.shape))?;
    let negative = options.negative()?;
    if let Some(note) = settings.shapes_without_rays_note(scene.glyph_sets.iter().map(|s| s.shape))
    {
        eprintln!("note: {note}");
    }
    // Written with the image and the depth map, all or nothing.
    let scene_file = save_scene.map(|path| (path, scene.to_json()));
    let common_scale = common_scale([&scene]);
    let variants = early_variants(&scene, &settings);
    let shapes: Vec<_> = scene.glyph_sets.iter().map(|set| set.shape).collect();
    let gpu_options = options.gpu_options();
    // The device and the scene's pipelines (most of a small render's time on lavapipe)
    // are made on a thread of their own while the glyphs are prepared.
    let (prepared, prepare_time, gpu) = std::thread::scope(|scope| {
        let device = scope.spawn(|| -> Result<(Gpu, HeadlessRenderer)> {
            let gpu = Gpu::headless(&gpu_options)?;
            let mut renderer = HeadlessRenderer::new(&gpu)?;
            // The fragment path's pipelines, where the device takes it.
            let path = settings
                .path
                .on_context(gpu.context(), settings.method, shapes);
            if path == glyphcast::RenderPath::Fragment {
                renderer.prepare_pipelines(&variants)?;
            }
            Ok((gpu, renderer))
        });
        let started = Instant::now();
        let prepared = prepare_render(scene, settings, negative);
        let prepare_time = started.elapsed();
        let gpu = device.join().unwrap_or(Err(glyphcast::Error::Thread {
            what: "device creation",
        }));
        (prepared, prepare_time, gpu)
    });
    // A bad scene is reported before a missing device, as when they came one by one.
    let prepared = prepared?;
    let (gpu, mut renderer) = gpu?;
    eprintln!("device: {}", gpu.info);
    let begun = Instant::now();
    let (w, h) = (prepared.width, prepared.height);
    let (sets, camera) = (&prepared.sets, &prepared.camera);
    let view = FrameView::new(camera, w, h)
        .with_underlay(underlay)
        .with_peaks(peaks);
    let overlays = Overlays {
        labels,
        caption: None,
        colorbar: options.colorbar_request(common_scale),
    };
    let image = render_figure(&mut renderer, &gpu, (sets, &view), &settings, &overlays)?;
    let glyphs = prepared.glyph_count();
    let gpu_time = image
        .gpu_ms
        .map_or_else(|| "n/a".to_owned(), |ms| format!("{ms:.1} ms"));
    eprintln!(
        "rendered {glyphs} glyphs at {w}x{h} on the {} path{}{}: prepare {:.1} ms, render \
         {:.1} ms (GPU {gpu_time})",
        image.path,
        match settings.path {
            glyphcast::RenderPath::Auto => " (auto)",
            _ => "",
        },
        match (image.culling, image.passes) {
            (glyphcast::render::Culling::EarlyOut, _) => {
                " in one pass front to back (hidden glyphs culled by early outs)".to_owned()
            }
            (_, 0 | 1) => String::new(),
            (_, n) => format!(" in {n} passes (hidden glyphs culled)"),
        },
        prepare_time.as_secs_f64() * 1e3,
        begun.elapsed().as_secs_f64() * 1e3
    );
    eprintln!("culling: {}", image.culling_report(&gpu, &settings)?);
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

/// Renders the panels of a montage (`--views`, `--lightbox`) into one image
/// (`render::compose::montage`) and writes it as [`render`] writes one view; `labels` labels every
/// panel, and a colour bar is appended to the whole montage.
pub fn render_montage(
    montage: VolumeMontage,
    output: &OutputArgs,
    options: &RenderArgs,
    labels: bool,
) -> Result<()> {
    let image = options.image_request()?;
    let settings = options.check()?;
    let negative = options.negative()?;
    let (mut scenes, peaks): (Vec<Scene>, Vec<Option<PeakSet>>) = montage
        .panels
        .into_iter()
        .map(|p| (p.scene, p.peaks))
        .unzip();
    for scene in &mut scenes {
        settings.check_shapes(scene.glyph_sets.iter().map(|s| s.shape))?;
        (scene.image.width, scene.image.height) = options.scaled(
            image.width.unwrap_or(scene.image.width),
            image.height.unwrap_or(scene.image.height),
        )?;
    }
    output.dpi()?;
    let common = common_scale(&scenes);
    let mut prepared = prepare_montage(scenes, montage.columns, settings, negative)?
        .with_underlays(montage.underlays)
        .with_captions(montage.captions);
    for (panel, peaks) in prepared.panels.iter_mut().zip(peaks) {
        panel.peaks = peaks;
    }
    let first = prepared.panels.first().ok_or(Error::Call {
        call: "render_montage",
        expected: "a montage of at least one panel",
    })?;
    let gpu = Gpu::headless(&options.gpu_options())?;
    eprintln!("device: {}", gpu.info);
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    let result = prepared.render(&mut renderer, &gpu, labels)?;
    // The montage's settings carry its one magnitude range (prepare_montage), so the
    // bar needs no extent of all panels' glyphs: the first panel's stands in, as in the
    // viewer (viewer::Panels::colorbar), and no copy of every panel's sets is made.
    let overlays = Overlays {
        colorbar: options.colorbar_request(common),
        ..Overlays::default()
    };
    let result = finish_figure(
        result,
        (&first.sets, &first.camera),
        &prepared.settings,
        &overlays,
    )?;
    let (cell_w, cell_h) = prepared.cell();
    eprintln!(
        "montage: {} panels of {cell_w}x{cell_h} in {} columns",
        prepared.panels.len(),
        prepared.columns()
    );
    write_outputs(&result, output, None)
}

/// Writes the PNG, the depth map and the scene file together: either all are new or all
/// are as they were (`io::atomic::write_all_atomic`).
fn write_outputs(
    image: &RenderedImage,
    output: &OutputArgs,
    scene_file: Option<(&Path, String)>,
) -> Result<()> {
    let (w, h) = (image.width, image.height);
    let png = glyphcast::io::png::encode_png_rgba8_at(
        &output.output,
        (w, h),
        &image.rgba,
        output.dpi()?,
    )?;
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
