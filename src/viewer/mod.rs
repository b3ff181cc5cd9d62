//! The interactive viewer (`glyphcast view`): a winit window with a Vulkan swapchain,
//! drawn by the same [`RayCastPass`](crate::render::raycast::RayCastPass) as everything
//! else, recorded into the window's command buffer with no distance attachment.
//!
//! One file per concern: `content` is what is shown (scene or volume slice, settings,
//! camera), `controls` maps keys and test scripts to [`Action`]s, `orbit` moves the
//! camera, `presenter` owns the swapchain frames, `app` is the winit event loop.
//!
//! The window is an add-on to the headless path: screenshots are rendered by the
//! [`HeadlessRenderer`](crate::render::headless::HeadlessRenderer) at the window's size
//! with its camera and settings, and a scripted run (`--frames`, `--script`) can read
//! back what the window showed (`--capture-window`) so tests can hold the two against
//! each other. Rendering is on demand (after input or a resize), not continuous: on a
//! software rasteriser a busy loop would take every core.
mod app;
mod content;
mod controls;
mod orbit;
mod presenter;

pub use content::{Content, ViewSource};
pub use controls::{Action, HELP, parse_script};
pub use orbit::{orbit, pan, zoom};

use crate::render::RenderSettings;
use crate::vk::GpuOptions;
use crate::{Error, Result};
use std::path::PathBuf;

/// How to run the viewer.
#[derive(Clone, Debug, Default)]
pub struct ViewerOptions {
    pub gpu: GpuOptions,
    pub settings: RenderSettings,
    /// The window's initial inner size (physical pixels).
    pub width: u32,
    pub height: u32,
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
}

/// Opens the window and runs until it is closed, or for `options.frames` frames.
pub fn run(source: ViewSource, options: ViewerOptions) -> Result<()> {
    if options.frames.is_none() && (!options.script.is_empty() || options.capture_window.is_some())
    {
        return Err(Error::Invalid(
            "--script and --capture-window need --frames N".into(),
        ));
    }
    let content = Content::new(source, options.settings)?;
    app::run(content, options)
}
