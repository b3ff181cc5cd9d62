//! `glyphcast qc`: one subject's quality-control figure set, a folder written all or
//! nothing (`glyphcast_dmri::qc`). The flags map onto a `QcRequest`; the output folder is
//! checked before any work.
use clap::Args;
use glyphcast::render::options::{RenderOptions, Value};
use glyphcast::vk::GpuOptions;
use glyphcast::{Result, Setting};
use glyphcast_dmri::qc::{QcRequest, check_output, make_set};
use glyphcast_dmri::volume::{ImageSource, VolumeRequest};
use std::path::PathBuf;

#[derive(Args)]
pub struct QcArgs {
    /// Fibre ODFs: a 4D image of SH coefficients (glyphcast fit --odf, MRtrix dwi2fod,
    /// DIPY), NIfTI or MRtrix.
    #[arg(value_name = "FOD")]
    fod: PathBuf,
    /// Output folder: written whole or not at all (an earlier set there is replaced, its
    /// own files only; a folder holding anything else, or an input, is refused).
    #[arg(short = 'o', long = "output", value_name = "OUTDIR")]
    output: PathBuf,
    /// Peaks of the ODFs (glyphcast peaks, MRtrix sh2peaks layout) for the peaks mosaic;
    /// checked against the ODFs' grid.
    #[arg(long, value_name = "IMAGE")]
    peaks: Option<PathBuf>,
    /// Axes of the --peaks directions: voxel or world, as for render --peaks-frame
    /// (default: the file's own; world for a NIfTI written by MRtrix's sh2peaks).
    #[arg(long, value_name = "FRAME", requires = "peaks")]
    peaks_frame: Option<String>,
    /// Tractogram (.tck, .trk, .trx, in scanner millimetres) for the tracks mosaic: the ODF
    /// mosaic's panels with the streamlines within half a voxel of each slice drawn over
    /// the glyphs as tubes (tracks-mosaic.png).
    #[arg(long, value_name = "FILE")]
    tracks: Option<PathBuf>,
    /// Mask of the brain (the ODFs' grid): the cuts, regions and glyphs stay inside it.
    /// Default: voxels with finite coefficients and a positive mean amplitude.
    #[arg(long, value_name = "IMAGE")]
    mask: Option<PathBuf>,
    /// Anatomical image (FA, T1, colour-FA) drawn under every panel.
    #[arg(long, value_name = "IMAGE")]
    underlay: Option<PathBuf>,
    /// The underlay's window LOW:HIGH (default: its 2nd to 98th percentile).
    #[arg(long, value_name = "LOW:HIGH", allow_hyphen_values = true)]
    underlay_range: Option<String>,
    /// SH basis of the ODFs, as for render --basis (default: the file's record).
    #[arg(long, value_name = "BASIS")]
    basis: Option<String>,
    /// The legacy variant of --basis.
    #[arg(long)]
    legacy: bool,
    /// Use --basis even where the file records another basis.
    #[arg(long)]
    force_basis: bool,
    /// Axes of the coefficients: voxel or world (as for render --frame).
    #[arg(long, value_name = "FRAME")]
    frame: Option<String>,
    /// radiological (default, as mrview) or neurological.
    #[arg(long, value_name = "CONVENTION")]
    orientation: Option<String>,
    /// Side of each panel in pixels, 64 to 4096 (default: 8 pixels per voxel of the
    /// volume's longest side, 400 to 1024).
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(64..=4096))]
    panel_size: Option<u32>,
    /// How glyphs are drawn, as for render --method (default exact).
    #[arg(long)]
    method: Option<String>,
    /// Negative lobes: hide (the default here: fibre ODFs' negative lobes are fitting
    /// noise) or abs.
    #[arg(long, value_name = "abs|hide", default_value = "hide")]
    negative: String,
    /// Samples per pixel: 1, 4 or 16.
    #[arg(long, default_value_t = 1, value_name = "1|4|16")]
    samples: u32,
    /// Vulkan device: part of its name or its index (also GLYPHCAST_DEVICE).
    #[arg(long)]
    device: Option<String>,
    /// Turn on the Vulkan validation layer (also GLYPHCAST_VALIDATION=1).
    #[arg(long)]
    validation: bool,
    /// No progress lines.
    #[arg(long)]
    quiet: bool,
}

impl QcArgs {
    fn request(&self) -> Result<QcRequest> {
        let mut render = RenderOptions::default();
        if let Some(method) = &self.method {
            render.set(Setting::Method, Value::Text(method))?;
        }
        render.set(Setting::Negative, Value::Text(&self.negative))?;
        render.samples = Some(self.samples);
        Ok(QcRequest {
            fod: self.fod.clone(),
            peaks: self.peaks.clone(),
            tracks: self.tracks.clone(),
            mask: self.mask.clone(),
            underlay: self.underlay.clone(),
            volume: VolumeRequest {
                basis: self.basis.clone(),
                legacy: self.legacy.then_some(true),
                force_basis: self.force_basis,
                frame: self.frame.clone(),
                orientation: self.orientation.clone(),
                // Named so that the request's checks see them; the set reads them itself.
                underlay: self.underlay.clone().map(ImageSource::File),
                underlay_range: self.underlay_range.clone(),
                peaks: self.peaks.clone().map(ImageSource::File),
                peaks_frame: self.peaks_frame.clone(),
                ..Default::default()
            },
            render,
            gpu: GpuOptions::from_env().with(self.device.clone(), self.validation),
            panel_size: self.panel_size,
        })
    }
}

pub fn run(args: &QcArgs) -> Result<()> {
    let request = args.request()?;
    // Every option is checked before the output folder and the inputs.
    request.render.settings()?;
    request.volume.options(Default::default())?;
    request
        .volume
        .check(glyphcast_dmri::volume::Coefficients::Sh)?;
    let inputs: Vec<&std::path::Path> = std::iter::once(args.fod.as_path())
        .chain(args.peaks.as_deref())
        .chain(args.tracks.as_deref())
        .chain(args.mask.as_deref())
        .chain(args.underlay.as_deref())
        .collect();
    check_output(&args.output, &inputs)?;
    let quiet = args.quiet;
    let progress = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    let set = make_set(&request, &progress)?;
    for note in &set.notes {
        eprintln!("note: {note}");
    }
    set.write(&args.output)?;
    progress(&format!(
        "wrote {} ({} files, device {})",
        args.output.display(),
        set.files.len(),
        set.device
    ));
    Ok(())
}
