//! `glyphcast view`: the interactive viewer on a scene file or a volume, with the render
//! command's scene source and options. The window's work is in `glyphcast_viewer`.
use super::render::{RenderArgs, SceneSource};
use super::volume::{VolumeArgs, panel_view};
use super::volume::{montage_needs_volume, save_scene_with_montage};
use clap::Args;
use glyphcast::error::{Message, Relation};
use glyphcast::io::atomic::{check_ending, check_outputs};
use glyphcast::render::underlay::Underlay;
use glyphcast::{Error, Result, Setting};
use glyphcast_dmri::volume::{ImageRequest, slice_framing};
use glyphcast_viewer::{MontageSource, ViewSource, ViewerOptions, parse_script};
use std::path::{Path, PathBuf};

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
    /// refine:SPEC, color:MODE, negative:abs|hide|toggle, slice:+N|-N, active:1|2|3,
    /// orbit:DX:DY, pan:DX:DY, zoom:F, reset, screenshot, wait. Needs --frames.
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
    /// Frames the window records ahead of the GPU (1 to 4): each waits only for the frame
    /// that used its slot before.
    #[arg(long, value_name = "N", default_value_t = glyphcast_viewer::FRAMES_IN_FLIGHT,
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=4))]
    pub frames_in_flight: usize,
}

pub fn run(args: &ViewArgs) -> Result<()> {
    args.source.check()?;
    if args.source.labels() {
        return Err(Error::conflict(
            Setting::Labels,
            Relation::Excludes,
            "view (the viewer names its orientation convention in its window title)",
        ));
    }
    let image = args.options.image_request()?;
    let settings = args.options.settings()?;
    args.options.check_colorbar(&settings)?;
    let negative = args.options.negative()?;
    let script = args
        .script
        .as_deref()
        .map(parse_script)
        .transpose()
        .map_err(|err| {
            // A bad event names itself (`'explode': ...`) after the flag.
            let message = match err {
                Error::Input { field, message, .. } => Message::from_pieces(
                    [vec![format!("{field}: ").into()], message.pieces().to_vec()].concat(),
                ),
                other => other.to_string().into(),
            };
            Error::Flag {
                flag: "--script",
                message,
            }
        })?
        .unwrap_or_default();
    check_run(args, args.source.volume.is_montage())?;
    let (source, underlay, (width, height)) = if args.source.volume.is_montage() {
        if args.source.scene.is_some() {
            return Err(montage_needs_volume());
        }
        let (montage, cell) = montage(&args.source.volume, image)?;
        (montage, None, cell)
    } else {
        single_view(&args.source, image)?
    };
    // The window (and its screenshots) at the scaled size of the same framing.
    let (width, height) = args.options.scaled(width, height)?;
    let options = ViewerOptions {
        gpu: args.options.gpu_options(),
        settings,
        negative,
        width,
        height,
        colorbar: args.options.wants_colorbar(),
        colorbar_label: args.options.colorbar_label().map(str::to_owned),
        frames: args.frames,
        script,
        screenshot: args.screenshot.clone(),
        capture_window: args.capture_window.clone(),
        save_scene: args.source.save_scene().map(PathBuf::from),
        underlay,
        frames_in_flight: args.frames_in_flight,
    };
    glyphcast_viewer::run(source, options).map_err(|e| match &args.source.scene {
        Some(path) => e.in_scene_file(path),
        None => e,
    })
}

/// The scripted-run and output flags, before the window opens: --script and
/// --capture-window need --frames; the outputs go through a render's checks (PNG and
/// JSON names, existing folders, no file named twice, none an input); a montage has no one scene to
/// save.
fn check_run(args: &ViewArgs, montage: bool) -> Result<()> {
    if args.frames.is_none() && (args.script.is_some() || args.capture_window.is_some()) {
        let flag = if args.script.is_some() {
            "--script"
        } else {
            "--capture-window"
        };
        return Err(Error::conflict(flag, Relation::Requires, "--frames N"));
    }
    let save_scene = args.source.save_scene();
    if montage && save_scene.is_some() {
        return Err(save_scene_with_montage());
    }
    let images = [
        ("--screenshot", args.screenshot.as_deref()),
        ("--capture-window", args.capture_window.as_deref()),
    ];
    for (flag, path) in images {
        if let Some(path) = path {
            check_ending(path, flag, &[".png"])?;
        }
    }
    if let Some(scene) = save_scene {
        check_ending(scene, "--save-scene", &[".json"])?;
    }
    let paths: Vec<&Path> = images
        .iter()
        .filter_map(|(_, path)| *path)
        .chain(save_scene)
        .collect();
    let inputs = args.source.input_paths();
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    check_outputs(&paths, &inputs)
}

/// The scene file or volume view (with its underlay) and the size of its image:
/// `--width` x `--height`, a side not given the scene's or the volume framing's.
fn single_view(
    source: &SceneSource,
    image: ImageRequest,
) -> Result<(ViewSource, Option<Underlay>, (u32, u32))> {
    let (source, underlay) = source.load_for_view(image)?;
    let size = match &source {
        ViewSource::Volume { view, .. } => view.scene.image,
        ViewSource::Scene(scene) => scene.image,
        ViewSource::Montage(_) => {
            return Err(Error::Call {
                call: "view::load",
                expected: "one view, not a montage",
            });
        }
    };
    let width = image.width.unwrap_or(size.width);
    let height = image.height.unwrap_or(size.height);
    Ok((source, underlay, (width, height)))
}

/// The panels of `--views` or `--lightbox` as `render` makes them, and the size of their
/// cells: `--width` x `--height`, else (a side not given) the largest panel's. Every
/// panel is framed for the cell, as `render` frames it with `--width` and `--height`
/// both given (without them, `render` centres a smaller panel in its cell instead).
fn montage(volume_args: &VolumeArgs, image: ImageRequest) -> Result<(ViewSource, (u32, u32))> {
    // Edge labels get a band free of glyphs, as in `render`.
    let image = ImageRequest {
        keep_edges: volume_args.labels,
        ..image
    };
    let (volume, plan) = volume_args.montage_panels(image)?;
    let (mut panels, columns) = (plan.panels, plan.columns);
    let mut cell = (image.width.unwrap_or(0), image.height.unwrap_or(0));
    if image.width.is_none() || image.height.is_none() {
        for options in &panels {
            let framing = slice_framing(&volume, options)?;
            cell.0 = cell.0.max(framing.image.width);
            cell.1 = cell.1.max(framing.image.height);
        }
    }
    let mut views = Vec::with_capacity(panels.len());
    for mut options in panels.drain(..) {
        options.image = ImageRequest {
            width: Some(cell.0),
            height: Some(cell.1),
            ..options.image
        };
        let view = panel_view(&volume, &options)?;
        views.push((options, view));
    }
    let underlays = volume_args
        .request()
        .panel_underlays(&volume, views.iter().map(|(_, view)| view))?;
    let source = ViewSource::Montage(Box::new(MontageSource {
        volume,
        panels: views,
        underlays,
        columns,
        lightbox: volume_args.lightbox.is_some(),
    }));
    Ok((source, cell))
}
