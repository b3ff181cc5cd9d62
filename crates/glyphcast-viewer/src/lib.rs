#![warn(missing_docs)]
//! The interactive viewer (`glyphcast view`): a winit window with a Vulkan swapchain,
//! drawn through the engine component
//! [`GlyphRenderer`](glyphcast::render::component::GlyphRenderer), as the headless renderer
//! and an embedding engine draw: glyphs uploaded once and shared by the viewer's frames
//! in flight (2 unless `--frames-in-flight` says otherwise), recorded into the window's
//! command buffer with no distance attachment.
//!
//! One file per concern: `content` is what one panel shows (scene or volume slice,
//! settings, camera), `panels` the window's panels (one, or a montage's), `layout` and
//! `figure` where panels and the colour bar's strip go (as `render` lays out its image),
//! `controls` maps keys and test scripts to [`Action`]s, `orbit` moves the camera,
//! `presenter` owns the swapchain and the glyph renderer, `slots` what each frame in
//! flight writes, `compose` the panels and strip copied into the frames, `app` is the
//! winit event loop.
//!
//! The window is an add-on to the headless path: screenshots are rendered by the
//! [`HeadlessRenderer`](glyphcast::render::headless::HeadlessRenderer) at the window's size
//! with its cameras and settings (a montage's panels and the colour bar composed as
//! `render` composes them), and a scripted run (`--frames`, `--script`) can read back
//! what the window showed (`--capture-window`) so tests can hold the two against each
//! other. Rendering is on demand (after input or a resize), not continuous: on a
//! software rasteriser a busy loop would take every core.
mod app;
mod compose;
mod content;
mod controls;
mod figure;
mod layout;
mod orbit;
mod panels;
mod presenter;
mod slots;

pub use content::{Content, MontageSource, ViewSource};
pub use controls::{Action, HELP, parse_script};
pub use orbit::{orbit, pan, zoom};
pub use panels::Panels;
pub use slots::FRAMES_IN_FLIGHT;

use glyphcast::glyph::NegativeMode;
use glyphcast::render::shaders::methods_for;
use glyphcast::render::{Method, RenderPath, RenderSettings};
use glyphcast::vk::GpuOptions;
use glyphcast::{Error, Result, Setting};
use std::path::PathBuf;

/// How to run the viewer.
#[derive(Clone, Debug, Default)]
pub struct ViewerOptions {
    /// Which device to open and whether the validation layer is on.
    pub gpu: GpuOptions,
    /// How glyphs are drawn at the start; keys change them afterwards.
    pub settings: RenderSettings,
    /// Replaces every glyph set's negative-lobe mode (`--negative`), if given.
    pub negative: Option<NegativeMode>,
    /// The size of each panel's cell at the start (physical pixels): the window's inner
    /// size for one view without a colour bar; a montage's window holds its grid of
    /// cells, and the colour bar's strip is added on the right.
    pub width: u32,
    /// The height of each panel's cell at the start (physical pixels).
    pub height: u32,
    /// Show the colour bar of `--color magnitude` in a strip of its own on the right
    /// (`--colorbar`), as `render --colorbar` appends it; while the colour is another
    /// mode there is no strip.
    pub colorbar: bool,
    /// The colour bar's label (`--colorbar-label`), else it names the unit.
    pub colorbar_label: Option<String>,
    /// Render this many frames, then finish (screenshot, capture) and exit: a scripted
    /// run for tests. None: run until the window is closed.
    pub frames: Option<u32>,
    /// Applied one per frame from the first frame on (only with `frames`).
    pub script: Vec<Action>,
    /// Where screenshots go: at the end of a scripted run, and for each `S` key press
    /// (numbered files `glyphcast-view-N.png` when None).
    pub screenshot: Option<PathBuf>,
    /// Scripted runs: also write the last frame as the window showed it (read back from
    /// the swapchain image) to this PNG.
    pub capture_window: Option<PathBuf>,
    /// With each screenshot, also write the scene as shown (glyphs of the current slice,
    /// camera, window size) as a scene file.
    pub save_scene: Option<PathBuf>,
    /// The anatomical underlay (`--underlay`) of a single view, drawn on the slice planes
    /// and moved with them; volume input only. A montage's come with its panels
    /// (`MontageSource::underlays`).
    pub underlay: Option<glyphcast::render::underlay::Underlay>,
    /// Frames recorded ahead of the GPU (`--frames-in-flight`); 0 takes
    /// [`FRAMES_IN_FLIGHT`].
    pub frames_in_flight: usize,
}

impl ViewerOptions {
    /// The frames in flight the window draws with.
    pub fn frames_in_flight(&self) -> usize {
        match self.frames_in_flight {
            0 => FRAMES_IN_FLIGHT,
            n => n,
        }
    }
}

/// Opens the window and runs until it is closed, or for `options.frames` frames. The
/// caller has checked the outputs (names and folders, as a render's) and that a script
/// and a window capture come with a frame count (the command line: `glyphcast view`).
pub fn run(source: ViewSource, options: ViewerOptions) -> Result<()> {
    let mut panels = Panels::new(source, options.settings, options.negative)?;
    // A montage's underlays came with its panels.
    if options.underlay.is_some() {
        panels.set_underlay(options.underlay.clone())?;
    }
    check_method(&panels, &options.settings)?;
    app::run(panels, options)
}

/// The ray caster that draws a panel's glyphs `sets` with `settings` on the device of
/// `ctx`: `auto` as everywhere ([`RenderPath::on_context`]), and the fragment path
/// wherever the window's settings ask for what the compute ray caster does not draw in a
/// window (shadows and ambient occlusion, methods other than exact, switched to with
/// the keys).
pub(crate) fn panel_path(
    settings: &RenderSettings,
    ctx: &glyphcast::vk::DeviceContext,
    sets: &[glyphcast::GlyphSetData],
) -> RenderPath {
    let path = settings
        .path
        .on_context(ctx, settings.method, sets.iter().map(|s| s.shape));
    match path {
        RenderPath::Compute if settings.casts_rays() || settings.method != Method::Exact => {
            RenderPath::Fragment
        }
        path => path,
    }
}

/// The window draws a method only where every glyph set has its shader, and the compute
/// ray caster only for glyphs it draws: anything else is refused before the window
/// opens.
fn check_method(panels: &Panels, settings: &RenderSettings) -> Result<()> {
    if settings.path == RenderPath::Compute {
        let shape = panels
            .panels
            .iter()
            .flat_map(|p| p.sets.iter().map(|s| s.shape))
            .find(|&shape| shape != glyphcast::glyph::GlyphShape::Polynomial);
        if let Some(shape) = shape {
            return Err(Error::setting_value(
                Setting::Path,
                settings.path,
                format!(
                    "the compute ray caster draws polynomial glyphs only, not {}",
                    shape.name()
                ),
            ));
        }
    }
    let layouts: Vec<_> = panels
        .panels
        .iter()
        .flat_map(|p| p.sets.iter().map(|s| s.layout))
        .collect();
    let methods = methods_for(&layouts);
    if !methods.contains(&settings.method) {
        let names: Vec<String> = methods.iter().map(ToString::to_string).collect();
        return Err(Error::setting_value(
            Setting::Method,
            settings.method,
            format!(
                "the viewer draws these glyphs with {} only",
                names.join(", ")
            ),
        ));
    }
    Ok(())
}
