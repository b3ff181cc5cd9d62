//! `glyphcast qc`: the quality-control figure set of one subject's fibre ODFs, written
//! as one folder, all or nothing (`io::folder`): an ODF mosaic (axial, coronal and
//! sagittal rows, three cuts each), a peaks mosaic (see [`figures::peaks_mosaic`]),
//! zoomed panels of the regions of highest anisotropy, `index.html` showing them with
//! the inputs' names and the orientation convention, and the sidecar `qc.json` (inputs
//! with sizes and SHA-256 checksums, settings, what was chosen, the figures' checksums,
//! glyphcast's version; the device and timings apart, under `run`).
//!
//! The volume is read once; one pass over it ([`survey`]) chooses the cuts and regions
//! from the data; only the slices drawn are built into glyphs; one device and renderer
//! draw every figure. For the same inputs and options the figures are the same bytes
//! (on the same device and driver), and so are `index.html` and `qc.json` but for `run`.
pub mod figures;
pub mod page;
pub mod survey;

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use crate::io::image::read_image;
use crate::io::tracks::{Tractogram, read_tractogram};
use crate::setting::DmriSetting;
use crate::volume::{
    CoefficientFrame, Coefficients, ImageRequest, Mask, Normalisation, Volume, VolumeRequest,
    load_mask, load_underlay,
};
use figures::{DrawContext, Figure, SharedUnderlay};
use glyphcast::io::folder::{check_folder_output, write_folder_atomic};
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::options::RenderOptions;
use glyphcast::vk::Gpu;
use glyphcast::{Error, Result};
use survey::{Survey, region_side, voxel_world};

/// The sidecar's name; a folder holding one is an earlier set, which a new run replaces.
pub const SIDECAR: &str = "qc.json";

/// The page's name.
pub const PAGE: &str = "index.html";

/// Default panel side: [`PIXELS_PER_VOXEL`] times the longest side of the volume in
/// voxels, within these pixels (a 10^3 volume gets 400, a 100 x 100 x 60 brain 800).
pub const DEFAULT_PANEL_SIZES: (u32, u32) = (400, 1024);

/// Pixels per voxel of the default panel side: glyphs of 0.9 voxel then span about 7
/// pixels in the mosaic, enough to see their colour and axis (the zoomed regions show
/// their lobes).
pub const PIXELS_PER_VOXEL: u32 = 8;

/// The default panel side for a volume of `dims` voxels (see [`DEFAULT_PANEL_SIZES`]).
pub fn default_panel_size(dims: [usize; 3]) -> u32 {
    let longest = dims.into_iter().max().unwrap_or(1) as u32;
    (PIXELS_PER_VOXEL.saturating_mul(longest)).clamp(DEFAULT_PANEL_SIZES.0, DEFAULT_PANEL_SIZES.1)
}

/// What to make a figure set of.
#[derive(Clone, Debug, Default)]
pub struct QcRequest {
    /// The fibre ODFs: a 4D SH volume (NIfTI or MRtrix).
    pub fod: PathBuf,
    /// Peaks of the ODFs (`glyphcast peaks`' layout), for the peaks mosaic.
    pub peaks: Option<PathBuf>,
    /// Only voxels where this mask is nonzero are looked at and drawn.
    pub mask: Option<PathBuf>,
    /// An anatomical image drawn under every panel.
    pub underlay: Option<PathBuf>,
    /// A tractogram (.tck, .trk, .trx) for the tracks mosaic: the ODF mosaic's panels with
    /// the streamlines near each slice drawn over the glyphs.
    pub tracks: Option<PathBuf>,
    /// The volume options that apply (basis, legacy, force basis, frame, orientation,
    /// underlay range); views, slices and the like are the set's own.
    pub volume: VolumeRequest,
    /// How glyphs are drawn (method, negative lobes, samples).
    pub render: RenderOptions,
    /// The device, and whether the validation layer runs.
    pub gpu: glyphcast::vk::GpuOptions,
    /// Each panel's side in pixels (the slice fitted inside); by default
    /// [`default_panel_size`].
    pub panel_size: Option<u32>,
}

/// A figure set in memory, ready to be written.
pub struct QcSet {
    /// File names in the folder and their bytes: the figures, the page, the sidecar.
    pub files: Vec<(String, Vec<u8>)>,
    /// Notes for the user (also on the page and in the sidecar).
    pub notes: Vec<String>,
    /// The device the figures were drawn on.
    pub device: String,
}

impl QcSet {
    /// Writes the set as the folder `dir`, all or nothing; an earlier set there is
    /// replaced (its listed files removed), a folder with any other entry refused
    /// ([`earlier_set`]).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let files: Vec<(&str, &[u8])> = self
            .files
            .iter()
            .map(|(name, bytes)| (name.as_str(), bytes.as_slice()))
            .collect();
        write_folder_atomic(dir, &files, &earlier_set)
    }
}

/// The files of an earlier figure set in `dir`, as its own sidecar lists them: the
/// sidecar, the page and each of `figures[].file`; `None` where `dir` holds no sidecar
/// that glyphcast wrote (a JSON object with `glyphcast_version` and a `figures` list of
/// plain file names). Another tool's `qc.json` is no set: its folder is refused.
pub fn earlier_set(dir: &Path) -> Option<Vec<String>> {
    let path = dir.join(SIDECAR);
    if !fs::symlink_metadata(&path).ok()?.is_file() {
        return None;
    }
    let text = fs::read_to_string(&path).ok()?;
    let document: serde_json::Value = serde_json::from_str(&text).ok()?;
    document.get("glyphcast_version")?.as_str()?;
    let mut names = vec![SIDECAR.to_owned(), PAGE.to_owned()];
    for figure in document.get("figures")?.as_array()? {
        let name = figure.get("file")?.as_str()?;
        let plain = Path::new(name).file_name().is_some_and(|n| n == name) && name != "..";
        if !plain {
            return None;
        }
        names.push(name.to_owned());
    }
    Some(names)
}

/// Checks, before any work, that the set can be written to `dir`, and that no input
/// lies inside it.
pub fn check_output(dir: &Path, inputs: &[&Path]) -> Result<()> {
    check_folder_output(dir, &earlier_set)?;
    glyphcast::io::atomic::check_not_inputs(&[dir], inputs)
}

/// An input file of the set, for the page and the sidecar.
#[derive(Clone, Debug)]
pub struct InputFile {
    /// What it is: fod, mask, underlay, peaks.
    pub role: &'static str,
    /// The path as given.
    pub path: PathBuf,
    /// Its size in bytes.
    pub bytes: u64,
    /// Its SHA-256, as lower-case hex.
    pub sha256: String,
}

/// Milliseconds since `start`.
fn ms(start: Instant) -> f64 {
    (start.elapsed().as_secs_f64() * 1e4).round() / 10.0
}

/// Makes the figure set of `request` (see the module notes); `progress` receives a line
/// per step.
pub fn make_set(request: &QcRequest, progress: &dyn Fn(&str)) -> Result<QcSet> {
    let started = Instant::now();
    let settings = request.render.settings()?;
    let negative = request.render.negative;
    if let Some(size) = request.panel_size {
        check_panel_size(size)?;
    }
    let inputs = input_files(request);
    // Checksums run beside the reading and drawing (the files are read twice, the
    // second time from the page cache).
    let hashing = std::thread::spawn(move || page::checksums(inputs));
    let mut timings: Vec<(&'static str, f64)> = Vec::new();

    let step = Instant::now();
    let volume = request.volume.read_volume(Coefficients::Sh, &request.fod)?;
    if let Some(basis) = volume.basis_summary() {
        progress(&format!("SH basis: {}: {basis}", volume.file));
    }
    let mask = request.mask.as_deref().map(load_mask).transpose()?;
    let underlay = read_underlay(request)?;
    let notes: Vec<String> = Vec::new();
    if let Some(peaks) = &request.peaks {
        check_peaks(peaks, volume.dims)?;
    }
    timings.push(("read", ms(step)));

    let step = Instant::now();
    let survey = Survey::of(&volume, mask.as_ref())?;
    let cuts = survey.cuts(&volume);
    let regions = survey.regions(region_side(volume.dims));
    timings.push(("survey", ms(step)));
    progress(&format!(
        "qc: {} voxels looked at; cuts {}; {} regions",
        survey.count,
        cuts.iter()
            .map(|c| format!("{} {:?}", c.plane.name(), c.indices))
            .collect::<Vec<_>>()
            .join(", "),
        regions.len()
    ));

    let step = Instant::now();
    let size = request
        .panel_size
        .unwrap_or_else(|| default_panel_size(volume.dims));
    let plans = plan_figures(request, &volume, mask, size, &cuts, &regions)?;
    let mut built = figures::build(&volume, plans)?;
    figures::size_alike(&mut built);
    timings.push(("build", ms(step)));

    let step = Instant::now();
    let gpu = Gpu::headless(&request.gpu)?;
    let device = gpu.info.to_string();
    let mut renderer = HeadlessRenderer::new(&gpu)?;
    timings.push(("device", ms(step)));
    progress(&format!("device: {device}"));

    let step = Instant::now();
    let context = DrawContext {
        gpu: &gpu,
        settings,
        negative,
        underlay: underlay.as_ref(),
        volume: &volume,
    };
    let peaks_frame = request.volume.peaks_frame()?;
    let peaks = request.peaks.as_deref().map(|path| (path, peaks_frame));
    let tracks = request
        .tracks
        .as_deref()
        .map(|path| read_tractogram(path).map(|t| (path, Arc::new(t))))
        .transpose()?;
    let overlays = Overlays {
        peaks,
        tracks: tracks.as_ref().map(|(path, t)| (*path, t)),
    };
    let drawn = draw_figures(&context, &mut renderer, built, overlays)?;
    timings.push(("render", ms(step)));

    let step = Instant::now();
    let mut files = drawn
        .iter()
        .map(|figure| {
            let image = &figure.image;
            let path = Path::new(&figure.file);
            glyphcast::io::png::encode_png_rgba8(path, image.width, image.height, &image.rgba)
                .map(|png| (figure.file.clone(), png))
        })
        .collect::<Result<Vec<_>>>()?;
    timings.push(("encode", ms(step)));
    let inputs = hashing.join().map_err(|_| Error::Thread {
        what: "the inputs' checksums",
    })??;
    timings.push(("total", ms(started)));
    let summary = page::Summary {
        request,
        panel_size: size,
        inputs: &inputs,
        volume: &volume,
        survey: &survey,
        cuts: &cuts,
        regions: &regions,
        figures: &drawn,
        files: &files,
        notes: &notes,
        device: &device,
        timings: &timings,
    };
    let sidecar = page::sidecar(&summary)?;
    let html = page::index_html(&summary);
    files.push((PAGE.into(), html.into_bytes()));
    files.push((SIDECAR.into(), sidecar.into_bytes()));
    Ok(QcSet {
        files,
        notes,
        device,
    })
}

/// The underlay asked for, read once for every panel, with its window.
fn read_underlay(request: &QcRequest) -> Result<Option<SharedUnderlay>> {
    let Some(path) = &request.underlay else {
        return Ok(None);
    };
    let (mut image, source) = load_underlay(path)?;
    if let Some((lo, hi)) = request.volume.underlay_range()? {
        image.set_window(lo, hi)?;
    }
    Ok(Some(SharedUnderlay {
        volume: Arc::new(image),
        source,
    }))
}

/// The set's figures, the mosaic first, with panels of `size` pixels showing the voxels
/// of `mask` (if any).
fn plan_figures(
    request: &QcRequest,
    volume: &Volume,
    mask: Option<Mask>,
    size: u32,
    cuts: &[survey::PlaneCuts],
    regions: &[survey::Region],
) -> Result<Vec<figures::FigurePlan>> {
    // Every panel is drawn with its edge labels: they get the band free of glyphs.
    let mut base = request.volume.options(ImageRequest {
        width: Some(size),
        height: Some(size),
        keep_edges: true,
    })?;
    base.mask = mask;
    // Sized per glyph first; `figures::size_alike` puts every glyph on one scale.
    base.norm = Normalisation::PerGlyph;
    let mut plans = vec![figures::mosaic_plan(&base, cuts)];
    for (rank, region) in regions.iter().enumerate() {
        let world = voxel_world(volume, region.centre()).to_array();
        plans.push(figures::zoom_plan(&base, volume, region, rank + 1, world));
    }
    Ok(plans)
}

/// What is drawn over the ODF mosaic's panels in figures of their own: the peaks (a
/// path, and the frame of their directions if named) and the streamlines (their file and
/// the tractogram read from it).
struct Overlays<'a> {
    peaks: Option<(&'a Path, Option<CoefficientFrame>)>,
    tracks: Option<(&'a Path, &'a Arc<Tractogram>)>,
}

/// Draws the built figures in order, the peaks mosaic and the tracks mosaic (where asked
/// for) after the ODF mosaic.
fn draw_figures(
    context: &DrawContext,
    renderer: &mut HeadlessRenderer,
    built: Vec<figures::BuiltFigure>,
    Overlays { peaks, tracks }: Overlays<'_>,
) -> Result<Vec<Figure>> {
    let mut built = built.into_iter();
    let mosaic = built.next().ok_or(Error::Call {
        call: "qc::run",
        expected: "a mosaic among the figures planned",
    })?;
    let peaks_figure = match peaks {
        Some((peaks, frame)) => Some(figures::peaks_mosaic(
            context, renderer, &mosaic, peaks, frame,
        )?),
        None => None,
    };
    let tracks_figure = match tracks {
        Some((path, tractogram)) => Some(figures::tracks_mosaic(
            context, renderer, &mosaic, path, tractogram,
        )?),
        None => None,
    };
    let mut drawn = vec![figures::render(context, renderer, mosaic)?];
    drawn.extend(peaks_figure);
    drawn.extend(tracks_figure);
    for figure in built {
        drawn.push(figures::render(context, renderer, figure)?);
    }
    Ok(drawn)
}

/// The inputs the request names, in the sidecar's order.
fn input_files(request: &QcRequest) -> Vec<(&'static str, PathBuf)> {
    let mut inputs = vec![("fod", request.fod.clone())];
    for (role, path) in [
        ("mask", &request.mask),
        ("underlay", &request.underlay),
        ("peaks", &request.peaks),
        ("tracks", &request.tracks),
    ] {
        if let Some(path) = path {
            inputs.push((role, path.clone()));
        }
    }
    inputs
}

/// The panel sizes accepted, in pixels a side.
pub const PANEL_SIZES: std::ops::RangeInclusive<u32> = 64..=4096;

/// Panels of [`PANEL_SIZES`] (a usage error otherwise).
fn check_panel_size(size: u32) -> Result<()> {
    if PANEL_SIZES.contains(&size) {
        return Ok(());
    }
    Err(Error::setting_value(
        DmriSetting::PanelSize,
        size,
        format!(
            "each panel of the set is {} to {} pixels a side",
            PANEL_SIZES.start(),
            PANEL_SIZES.end()
        ),
    ))
}

/// The peaks image must be peaks of these ODFs: 4D, 3 values per peak, on their grid.
fn check_peaks(path: &Path, dims: [usize; 3]) -> Result<()> {
    let image = read_image(path)?;
    let shape = image.shape(4);
    let file = path.display().to_string();
    if shape.len() != 4 || shape[3] == 0 || shape[3] % 3 != 0 {
        return Err(Error::input(
            &file,
            "dim",
            format!(
                "{shape:?}: peaks are a 4D image of 3 values per peak (glyphcast peaks, \
                 MRtrix sh2peaks)"
            ),
        ));
    }
    if shape[..3] != dims {
        return Err(Error::input(
            &file,
            "dim",
            format!(
                "the peaks' grid {:?} is not the ODFs' {dims:?}",
                &shape[..3]
            ),
        ));
    }
    Ok(())
}
