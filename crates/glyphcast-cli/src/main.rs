//! The `glyphcast` command line. Each subcommand's options and work live in `src/cli/`.
mod cli;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use cli::render::{OutputArgs, RenderArgs, SceneSource};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "glyphcast",
    version,
    about = "GPU ray casting of higher-order tensor and SH glyphs"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file (docs/scene-format.md) or a volume to a PNG, and optionally a depth map.
    #[command(after_help = "Guide: docs/guide/figures.md; every render setting: \
                            docs/guide/settings.md")]
    Render {
        #[command(flatten)]
        source: Box<SceneSource>,
        #[command(flatten)]
        output: OutputArgs,
        #[command(flatten)]
        options: RenderArgs,
    },
    /// Show a scene file or a volume in a window: orbit, pan and zoom with the mouse,
    /// keys for the method, step, refinement, colour, negative lobes and the slice.
    #[command(after_help = "Guide: docs/guide/viewer.md")]
    View(Box<cli::view::ViewArgs>),
    /// Render the built-in demo scene (a field of crossing-fibre glyphs).
    ///
    /// The glyphs are framed centred at the --width and --height given, whole at any
    /// aspect ratio.
    #[command(after_help = "Guide: docs/guide/command-line.md")]
    Demo {
        /// Show a field of rotated copper crystals as stiffness-tensor glyphs instead.
        #[arg(long)]
        stiffness: bool,
        #[command(flatten)]
        output: OutputArgs,
        #[command(flatten)]
        options: RenderArgs,
        /// Also write the demo scene as a scene file.
        #[arg(long, value_name = "FILE")]
        save_scene: Option<PathBuf>,
    },
    /// Measure every method against the float64 reference on the accuracy suite.
    #[command(after_help = "Guide: docs/guide/accuracy.md")]
    Accuracy(cli::accuracy::AccuracyArgs),
    /// GPU timings of the glyph pass: one scene or workload, or a sweep.
    #[command(after_help = "Guide: docs/guide/performance.md")]
    Bench(cli::bench::BenchArgs),
    /// Fit tensor, SH or fibre-ODF (CSD, CSA, Q-ball) coefficients to a DWI series
    /// (writes a 4D NIfTI or MRtrix image).
    #[command(after_help = "Guide: docs/guide/fitting.md")]
    Fit(cli::fit::FitArgs),
    /// Find up to N maxima per voxel of an ODF image (MRtrix sh2peaks' layout).
    #[command(after_help = "Guide: docs/guide/fitting.md")]
    Peaks(cli::peaks::PeaksArgs),
    /// Write one subject's quality-control figure set of fibre ODFs into a folder: ODF
    /// mosaic, zoomed regions, index.html and the qc.json sidecar.
    #[command(
        after_help = "Guide: docs/guide/qc.md; cohorts on a cluster (SLURM job arrays, \
                      Nipype): docs/guide/cohorts.md"
    )]
    Qc(Box<cli::qc::QcArgs>),
    /// Write a scene of stiffness glyphs from Voigt matrices (text, CSV or JSON), and the
    /// elastic extremes and averages (--summary).
    #[command(after_help = "Guide (definitions, units and accuracy): docs/guide/materials.md")]
    Stiffness(cli::stiffness::StiffnessArgs),
    /// Write the command-line reference into a folder: a Markdown page per command, man
    /// pages and shell completions (tools/gen-docs.sh writes docs/reference/).
    #[command(hide = true)]
    Reference {
        /// The folder (made if missing).
        #[arg(value_name = "DIR")]
        dir: PathBuf,
    },
}

fn main() {
    // A negative number after a flag is its value (`--offset -0.5`), as in most tools;
    // clap otherwise takes it for a flag and suggests `--`, which would be wrong here.
    let command = Cli::command().mut_subcommands(|sub| sub.allow_negative_numbers(true));
    let cli = Cli::from_arg_matches(&command.get_matches()).unwrap_or_else(|e| e.exit());
    remove_temporaries_on_interrupt();
    if let Err(e) = run(cli) {
        eprintln!("error: {}", cli::flags::message(&e));
        std::process::exit(cli::flags::exit_code(&e));
    }
}

/// SIGINT and SIGTERM end the process as they would by default (exit 130 or 143, as a
/// shell reports a death by signal), but first remove the temporaries of a write in
/// progress and let a set of outputs finish its renames (`io::atomic`). Without the
/// handler (should installing it fail) the defaults stay, with the old risk of a stray
/// hidden temporary; that is reported.
fn remove_temporaries_on_interrupt() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
        Ok(signals) => signals,
        Err(err) => {
            eprintln!(
                "warning: no interrupt handler ({err}): an interrupted write may leave a temporary file"
            );
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            glyphcast::io::atomic::exit_removing_temporaries(128 + signal)
        }
    });
}

fn run(cli: Cli) -> glyphcast::Result<()> {
    match cli.command {
        Command::Render {
            source,
            output,
            options,
        } => {
            // Every option value is checked before any file is read.
            source.check()?;
            options.check()?;
            output.check()?;
            cli::render::check_outputs(&output, source.save_scene(), &source.input_paths())?;
            if source.volume.is_montage() {
                if source.save_scene().is_some() {
                    return Err(cli::volume::save_scene_with_montage());
                }
                if source.scene.is_some() {
                    return Err(cli::volume::montage_needs_volume());
                }
            }
            match source.load(options.image_request()?)? {
                cli::render::Loaded::Scene(scene, underlay, peaks) => cli::render::render(
                    scene,
                    &output,
                    &options,
                    source.save_scene(),
                    source.labels(),
                    underlay.as_ref(),
                    peaks.as_ref(),
                )
                .map_err(|e| match &source.scene {
                    Some(path) => e.in_scene_file(path),
                    None => e,
                }),
                cli::render::Loaded::Montage(montage) => {
                    cli::render::render_montage(montage, &output, &options, source.labels())
                }
            }
        }
        Command::View(args) => cli::view::run(&args),
        Command::Demo {
            stiffness,
            output,
            options,
            save_scene,
        } => {
            options.check()?;
            output.check()?;
            cli::render::check_outputs(&output, save_scene.as_deref(), &[])?;
            let mut scene = if stiffness {
                glyphcast::demo::stiffness_demo_scene()
            } else {
                glyphcast::demo::demo_scene()
            };
            // Framed at the size asked for, centred, with no glyph cut at any aspect.
            let image = options.image_request()?;
            let width = image.width.unwrap_or(scene.image.width);
            let height = image.height.unwrap_or(scene.image.height);
            glyphcast::demo::frame_glyphs(&mut scene, width, height);
            cli::render::render(
                scene,
                &output,
                &options,
                save_scene.as_deref(),
                false,
                None,
                None,
            )
        }
        Command::Accuracy(args) => cli::accuracy::run(&args),
        Command::Bench(args) => cli::bench::run(&args),
        Command::Fit(args) => cli::fit::run(args),
        Command::Peaks(args) => cli::peaks::run(args),
        Command::Qc(args) => cli::qc::run(&args),
        Command::Stiffness(args) => cli::stiffness::run(args),
        Command::Reference { dir } => cli::reference::write(&Cli::command(), &dir),
    }
}

#[cfg(test)]
mod tests {
    use super::Cli;
    use clap::CommandFactory;
    use glyphcast::Setting;

    /// Every command's help names its guide page, and the page is there.
    #[test]
    fn every_command_names_its_guide_page() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
        let command = Cli::command();
        let commands = command.get_subcommands();
        for sub in commands.filter(|s| !s.is_hide_set() && s.get_name() != "help") {
            let after = sub
                .get_after_help()
                .map(|h| h.to_string())
                .unwrap_or_default();
            let page = after
                .split_whitespace()
                .find(|w| w.starts_with("docs/guide/"))
                .map(|w| w.trim_end_matches([';', ',', '.', ')']))
                .unwrap_or_else(|| panic!("{}: no guide page in {after:?}", sub.get_name()));
            let path = std::path::Path::new(root).join(page);
            assert!(path.is_file(), "{}: {page} is missing", sub.get_name());
        }
    }

    /// docs/reference/ holds what `glyphcast reference` makes of the command line now
    /// (tools/gen-docs.sh rewrites it).
    #[test]
    fn the_committed_reference_is_current() {
        let root =
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/reference"));
        let files = super::cli::reference::files(&Cli::command()).unwrap();
        assert!(files.len() > 20, "{}", files.len());
        // No file is there that the reference no longer makes.
        for folder in ["cli", "man", "completions"] {
            for entry in std::fs::read_dir(root.join(folder)).unwrap() {
                let name = format!("{folder}/{}", entry.unwrap().file_name().to_string_lossy());
                assert!(
                    files.iter().any(|(path, _)| *path == name),
                    "docs/reference/{name} is no longer made: run bash tools/gen-docs.sh"
                );
            }
        }
        for (path, bytes) in files {
            let committed = std::fs::read(root.join(&path)).unwrap_or_default();
            assert!(
                committed == bytes,
                "docs/reference/{path} is stale: run bash tools/gen-docs.sh"
            );
        }
    }

    /// Every setting the library names is spelled as a flag some subcommand has.
    #[test]
    fn every_setting_is_spelled_as_a_real_flag() {
        let command = Cli::command();
        let mut longs: Vec<String> = Vec::new();
        for sub in command.get_subcommands() {
            longs.extend(
                sub.get_arguments()
                    .filter_map(|a| a.get_long())
                    .map(|l| format!("--{l}")),
            );
        }
        let render = glyphcast::render::table::RENDER_SETTINGS
            .iter()
            .map(|s| &s.setting);
        let dmri = glyphcast_dmri::setting::DmriSetting::ALL.iter();
        for &setting in Setting::ALL.iter().chain(render).chain(dmri) {
            let flag = super::cli::flags::flag(setting);
            assert!(longs.contains(&flag), "{setting:?}: no {flag}");
        }
    }

    #[test]
    fn setting_errors_are_usage_errors_in_the_flags_words() {
        let err = glyphcast::Error::setting_value(Setting::MagnitudeRange, "'1-2'", "not LOW:HIGH");
        assert_eq!(
            super::cli::flags::message(&err),
            "--magnitude-range '1-2': not LOW:HIGH"
        );
        assert_eq!(super::cli::flags::exit_code(&err), 2);
        let input = glyphcast::Error::input(
            "v.nii",
            "voxels",
            glyphcast::message!["no voxel below ", Setting::MinAmplitude],
        );
        assert_eq!(
            super::cli::flags::message(&input),
            "v.nii: voxels: no voxel below --min-amplitude"
        );
        assert_eq!(super::cli::flags::exit_code(&input), 1);
    }
}
