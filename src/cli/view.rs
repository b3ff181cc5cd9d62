//! `glyphcast view`: the interactive viewer on a scene file or a volume, with the render
//! command's scene source and options. The window's work is in `glyphcast::viewer`.
use super::render::{RenderArgs, SceneSource};
use clap::Args;
use glyphcast::viewer::{ViewerOptions, parse_script};
use glyphcast::{Error, Result};
use std::path::PathBuf;

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub source: SceneSource,
    #[command(flatten)]
    pub options: RenderArgs,
    /// Render N frames, write --screenshot (and --capture-window) and exit: a scripted,
    /// self-ending run for tests.
    #[arg(long, value_name = "N", help_heading = "Scripted runs")]
    pub frames: Option<u32>,
    /// Events applied one per frame, comma-separated: resize:WxH, method:NAME, step:S,
    /// refine:SPEC, color:MODE, negative:abs|hide|toggle, slice:+N|-N, orbit:DX:DY,
    /// pan:DX:DY, zoom:F, reset, screenshot, wait. Needs --frames.
    #[arg(long, value_name = "EVENTS", help_heading = "Scripted runs")]
    pub script: Option<String>,
    /// PNG for screenshots, rendered headless at the window's size and camera: written at
    /// the end of a scripted run and by the S key (default glyphcast-view-N.png).
    #[arg(long, value_name = "PNG")]
    pub screenshot: Option<PathBuf>,
    /// With --frames: also write the last frame as the window showed it (read back from
    /// the swapchain).
    #[arg(long, value_name = "PNG", help_heading = "Scripted runs")]
    pub capture_window: Option<PathBuf>,
}

pub fn run(args: &ViewArgs) -> Result<()> {
    if args.source.labels() {
        return Err(glyphcast::Error::Usage(
            "--labels applies to render; the viewer names its orientation convention in the \
             window title"
                .into(),
        ));
    }
    if args.options.wants_colorbar() {
        return Err(glyphcast::Error::Usage(
            "--colorbar applies to render: the viewer draws no colour bar".into(),
        ));
    }
    let image = args.options.image_request()?;
    let settings = args.options.settings()?;
    let negative = args.options.negative()?;
    let script = args
        .script
        .as_deref()
        .map(parse_script)
        .transpose()
        .map_err(Error::into_usage)?
        .unwrap_or_default();
    let (source, underlay) = args.source.load_for_view(image)?;
    let (width, height) = match &source {
        glyphcast::viewer::ViewSource::Scene(scene) => (scene.image.width, scene.image.height),
        glyphcast::viewer::ViewSource::Volume { view, .. } => {
            (view.scene.image.width, view.scene.image.height)
        }
    };
    let options = ViewerOptions {
        gpu: args.options.gpu_options(),
        settings,
        negative,
        width: image.width.unwrap_or(width),
        height: image.height.unwrap_or(height),
        frames: args.frames,
        script,
        screenshot: args.screenshot.clone(),
        capture_window: args.capture_window.clone(),
        save_scene: args.source.save_scene().map(PathBuf::from),
        underlay,
    };
    glyphcast::viewer::run(source, options)
}
