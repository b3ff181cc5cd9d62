//! Volume input for `glyphcast render` and `view`: a slice (or a montage of slices) of a
//! 4D NIfTI or MRtrix volume of SH coefficients (`--sh`) or Cartesian tensor
//! coefficients (`--tensor`) becomes the scene. The work, every option's parsing, default
//! and check included, is `glyphcast_dmri::volume::VolumeRequest`'s, shared with the Python
//! module; this file maps the flags onto a request and reports what was drawn and what
//! was left out.
//!
//! `--basis` has no default of its own: it is what the file records (`glyphcast fit`'s
//! description; tournier07 for MRtrix images, MRtrix's only basis), and without a record
//! it must be given, since guessing wrong draws plausible but wrong glyphs
//! (`glyphcast_dmri::volume::resolve_basis`).
use clap::Args;
use glyphcast::Result;
use glyphcast::error::Relation;
use glyphcast::scene::Scene;
use glyphcast::{Error, Setting};
use glyphcast_dmri::volume::{
    Coefficients, ImageRequest, ImageSource, MontagePlan, Volume, VolumeFigure, VolumeOptions,
    VolumeRequest, VolumeScene, show_block, volume_scene,
};
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct VolumeArgs {
    /// 4D image of SH coefficients, [x, y, z, (L+1)(L+2)/2] for an even band L <= 12:
    /// NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz, .mih); see --frame.
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub sh: Option<PathBuf>,
    /// SH basis of --sh: tournier07 or descoteaux07 (with --legacy for the legacy
    /// variant), or mrtrix (= tournier07, dwi2fod's output), dipy (= descoteaux07
    /// legacy, DIPY's default) or dipy-new (= descoteaux07). A bare descoteaux07 on a
    /// file that records no basis is refused: say dipy (or --legacy) or dipy-new.
    /// Default: the basis the file records (glyphcast fit writes it), tournier07 for
    /// MRtrix images without a record.
    #[arg(long, value_name = "BASIS", help_heading = "Volume input")]
    pub basis: Option<String>,
    /// Use --basis even where the file records another basis.
    #[arg(long, help_heading = "Volume input")]
    pub force_basis: bool,
    /// Axes of the coefficients: voxel (the image's voxel axes, as DIPY writes them;
    /// glyphs are turned by the affine's rotation) or world (scanner axes, as MRtrix
    /// stores them and glyphcast fit writes them). Default: voxel for NIfTI, world for
    /// MRtrix images (unless the header says glyphcast_frame: voxel).
    #[arg(long, value_name = "FRAME", help_heading = "Volume input")]
    pub frame: Option<String>,
    /// The legacy variant of --basis (DIPY's legacy=True; MRtrix 0.2 for tournier07).
    #[arg(long, help_heading = "Volume input")]
    pub legacy: bool,
    /// Draw SH bands up to L only.
    #[arg(long, value_name = "L", help_heading = "Volume input")]
    pub lmax: Option<u32>,
    /// 4D NIfTI or MRtrix image of Cartesian tensor coefficients: order 2 in the order of
    /// --tensor-order, higher orders in the scene format's order.
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub tensor: Option<PathBuf>,
    /// Stored order of an order-2 --tensor's six entries: glyphcast (xx, xy, xz, yy, yz,
    /// zz; also FSL's dtifit), fsl, mrtrix (xx, yy, zz, xy, xz, yz; dwi2tensor) or dipy
    /// (xx, xy, yy, xz, yz, zz; lower_triangular). Default: what the file records
    /// (glyphcast fit writes it), mrtrix for .mif, else glyphcast, refused where the values
    /// show another order.
    #[arg(long, value_name = "ORDER", help_heading = "Volume input")]
    pub tensor_order: Option<String>,
    /// Tensor order of --tensor (1 to 12).
    #[arg(long, value_name = "N", help_heading = "Volume input")]
    pub order: Option<u32>,
    /// --tensor holds all 3^N entries, row-major, instead of the unique ones.
    #[arg(long, help_heading = "Volume input")]
    pub nonsymmetric: bool,
    /// Slice to draw: axial, coronal or sagittal, the world's planes (across scanner z, y
    /// or x; the voxel plane closest to it: constant k, j or i for an axial acquisition),
    /// optionally :INDEX along that voxel axis (default: the middle axial slice).
    #[arg(long, value_name = "AXIS[:INDEX]", help_heading = "Volume input")]
    pub slice: Option<String>,
    /// Three orthogonal slices at once instead of --slice: voxel indices I,J,K of the
    /// sagittal, coronal and axial slice, or mid (the middle of each); seen in perspective
    /// from superior-left, anterior (radiological) or posterior (neurological).
    #[arg(long, value_name = "I,J,K|mid", help_heading = "Volume input")]
    pub slices: Option<String>,
    /// Every voxel of --voxels (the whole volume without it) as glyphs in 3D instead of a
    /// slice, in perspective from the corner --slices is seen from, framed whole; with
    /// --mask, --scale, --norm and --min-amplitude as for slices, and --peaks in every
    /// voxel. At most 100000 glyphs; not with --slice, --slices, --views, --lightbox or
    /// --underlay.
    #[arg(long, help_heading = "Volume input")]
    pub block: bool,
    /// Voxel index ranges i0:i1,j0:j1,k0:k1 (end exclusive, ends optional), intersected
    /// with the slice; with --block, the block drawn.
    #[arg(
        long,
        value_name = "RANGES",
        help_heading = "Volume input",
        allow_hyphen_values = true
    )]
    pub voxels: Option<String>,
    /// 3D NIfTI or MRtrix mask of the volume's shape: glyphs only where it is nonzero.
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub mask: Option<PathBuf>,
    /// World radius of a full-size glyph (default: 0.45 times the smallest voxel size).
    #[arg(long, value_name = "S", help_heading = "Volume input")]
    pub scale: Option<f64>,
    /// Glyph sizes: sqrt (the default: the glyph at the 95th percentile of the glyph
    /// sizes at --scale, a smaller one at --scale times the square root of its size
    /// over that one's, a larger one at --scale), robust (one factor for all: the
    /// largest glyph that is no outlier at --scale, an outlier being more than 1.5
    /// times the 99th percentile of the glyph sizes, drawn at --scale itself), global
    /// (one factor for all, the largest at --scale), per-glyph (all the same size) or
    /// none (amplitude times --scale).
    #[arg(long, value_name = "MODE", help_heading = "Volume input")]
    pub norm: Option<String>,
    /// Leave out glyphs whose largest radius is below A (data units).
    #[arg(long, value_name = "A", help_heading = "Volume input")]
    pub min_amplitude: Option<f64>,
    /// Perspective camera instead of orthographic.
    #[arg(long, help_heading = "Volume input")]
    pub perspective: bool,
    /// radiological (the subject's right on the image's left in axial and coronal views,
    /// as mrview shows them; the default) or neurological (right on the right). Sagittal
    /// views have anterior on the left in both.
    #[arg(long, value_name = "CONVENTION", help_heading = "Volume input")]
    pub orientation: Option<String>,
    /// Anatomical underlay drawn as a plane behind each slice's glyphs (of every panel
    /// of --views/--lightbox), in the glyphs' depth buffer: a 3D NIfTI or MRtrix image
    /// (FA, T1) or an RGB one [x, y, z, 3] (colour-FA), sampled trilinearly through its
    /// own affine (the grids may differ).
    #[arg(long, value_name = "IMAGE", help_heading = "Underlay")]
    pub underlay: Option<PathBuf>,
    /// The underlay's window: LOW is drawn black, HIGH white (each RGB channel alike).
    /// Default: the 2nd to 98th percentile of its finite values.
    #[arg(
        long,
        value_name = "LOW:HIGH",
        help_heading = "Underlay",
        allow_hyphen_values = true
    )]
    pub underlay_range: Option<String>,
    /// Where the underlay's plane lies: back (behind the glyphs: as far behind the
    /// slice, seen from the camera, as the largest glyph reaches; the default) or centre
    /// (through the voxel centres, hiding each glyph's far half).
    #[arg(long, value_name = "back|centre", help_heading = "Underlay")]
    pub underlay_plane: Option<String>,
    /// Glyph surface: polynomial (the glyph of the tensor or SH series, the default) or
    /// ellipsoid (order-2 tensors: the DTI ellipsoid { D^(1/2) u }, semi-axes
    /// sqrt(eigenvalues), eigenvalues below 1e-6 of the largest raised to that floor).
    /// For a scene file it sets every glyph set's `shape`.
    #[arg(long, value_name = "SHAPE")]
    pub glyph: Option<String>,
    /// Write the anatomical directions (L/R, A/P, S/I) at the image's edges (of every
    /// panel of a montage).
    #[arg(long, help_heading = "Volume input")]
    pub labels: bool,
    /// One image (view: one window) with a panel per view, left to right: a
    /// comma-separated list of axial, coronal and sagittal (any subset, any order; each
    /// optionally :INDEX as for --slice), each panel --width x --height.
    #[arg(long, value_name = "VIEW,...", help_heading = "Volume input")]
    pub views: Option<String>,
    /// N evenly spaced slices along the --slice plane (default axial) in a grid of
    /// ceil(sqrt(N)) columns, each panel --width x --height.
    #[arg(long, value_name = "N", help_heading = "Volume input")]
    pub lightbox: Option<usize>,
    /// Fibre peaks drawn in the voxels of the slices, as capsules through the voxel
    /// centres in the glyphs' depth buffer: a 4D image of 3 values per peak, direction
    /// times amplitude, NaN where absent (glyphcast peaks, MRtrix sh2peaks), or with
    /// --peak-values DIPY's unit peak_dirs (4D [x, y, z, 3N] or 5D [x, y, z, N, 3]). On
    /// the glyphs' grid; alone (without --sh/--tensor) the peaks' grid frames the view.
    /// Directions are in the file's own frame (voxel axes for NIfTI, scanner axes for
    /// MRtrix images unless the header says otherwise); --peaks-frame names another.
    #[arg(long, value_name = "IMAGE", help_heading = "Peaks")]
    pub peaks: Option<PathBuf>,
    /// Axes of the --peaks directions: voxel or world (scanner). Default: voxel for NIfTI,
    /// world for MRtrix images. MRtrix's sh2peaks writes scanner axes into a NIfTI too:
    /// give world for such a file.
    #[arg(long, value_name = "FRAME", help_heading = "Peaks")]
    pub peaks_frame: Option<String>,
    /// DIPY's peak_values [x, y, z, N]: the amplitudes of --peaks, whose directions are
    /// then unit vectors (the DIPY layout).
    #[arg(long, value_name = "IMAGE", help_heading = "Peaks")]
    pub peak_values: Option<PathBuf>,
    /// Peak colour: direction (RGB = |x|, |y|, |z| of the world direction, the default),
    /// a name (white, black, grey, red, green, blue, yellow, cyan, magenta), #rrggbb or
    /// r,g,b (0-255).
    #[arg(long, value_name = "COLOR", help_heading = "Peaks")]
    pub peaks_color: Option<String>,
    /// Peak lengths: global (proportional to the amplitude, the longest drawn gets
    /// --peaks-scale; the default), unit (all --peaks-scale) or none (amplitude times
    /// --peaks-scale).
    #[arg(long, value_name = "MODE", help_heading = "Peaks")]
    pub peaks_norm: Option<String>,
    /// World half length of the longest peak (default: 0.5 times the smallest voxel size,
    /// so that it spans its voxel).
    #[arg(long, value_name = "S", help_heading = "Peaks")]
    pub peaks_scale: Option<f64>,
    /// Peak diameter in pixels (default 2; at the target in a perspective view).
    #[arg(long, value_name = "PX", help_heading = "Peaks")]
    pub peaks_width: Option<f64>,
    /// Streamlines drawn as tubes with the glyphs, in one depth buffer (tubes and lobes
    /// hide each other where they are in front): a tractogram, MRtrix .tck, TrackVis .trk
    /// or TRX .trx, read in scanner millimetres as its format defines, the frame the
    /// volume's glyphs are placed in.
    #[arg(long, value_name = "FILE", help_heading = "Tracks")]
    pub tracks: Option<PathBuf>,
    /// Tube colour: direction (RGB = |x|, |y|, |z| of each segment's direction, the
    /// default), scalar[:NAME] (a value stored per point, a TrackVis scalar or a TRX dpv,
    /// the first one without NAME, through viridis over its range in the file), a name
    /// (white, black, grey, red, green, blue, yellow, cyan, magenta), #rrggbb or r,g,b
    /// (0-255).
    #[arg(long, value_name = "COLOR", help_heading = "Tracks")]
    pub tracks_color: Option<String>,
    /// Tube radius in millimetres (default 0.15).
    #[arg(long, value_name = "MM", help_heading = "Tracks")]
    pub tracks_radius: Option<f64>,
    /// tubes (the default: ray-cast exactly, tubes and lobes hide each other at their
    /// surfaces) or lines (flat, unlit ribbons of the tubes' width, at least a pixel,
    /// at the streamline's depth: much faster for a whole brain's overlapping
    /// streamlines on lavapipe, not exact).
    #[arg(long, value_name = "tubes|lines", help_heading = "Tracks")]
    pub tracks_style: Option<String>,
    /// Draw at most N streamlines: every k-th, k the smallest that leaves at most N.
    #[arg(long, value_name = "N", help_heading = "Tracks")]
    pub tracks_max: Option<usize>,
    /// On slice views, only the parts of streamlines within MM millimetres of a slice's
    /// plane, each segment clipped there (as mrview crops tracks to a slab); a --block
    /// draws them whole.
    #[arg(long, value_name = "MM", help_heading = "Tracks")]
    pub slab: Option<f64>,
    /// Also write the scene that is rendered as a scene file (with the image, all or
    /// nothing).
    #[arg(long, value_name = "FILE")]
    pub save_scene: Option<PathBuf>,
}

impl VolumeArgs {
    /// The images the volume flags name (coefficients, mask, underlay, peaks).
    pub fn input_paths(&self) -> Vec<&Path> {
        [
            &self.sh,
            &self.tensor,
            &self.mask,
            &self.underlay,
            &self.peaks,
            &self.peak_values,
        ]
        .into_iter()
        .filter_map(|path| path.as_deref())
        .collect()
    }

    pub fn is_given(&self) -> bool {
        self.sh.is_some() || self.tensor.is_some() || self.peaks.is_some()
    }

    /// The first flag given that only means something for volume input.
    pub fn volume_only_flag(&self) -> Option<&'static str> {
        let given = [
            ("--basis", self.basis.is_some()),
            ("--force-basis", self.force_basis),
            ("--frame", self.frame.is_some()),
            ("--legacy", self.legacy),
            ("--lmax", self.lmax.is_some()),
            ("--order", self.order.is_some()),
            ("--nonsymmetric", self.nonsymmetric),
            ("--tensor-order", self.tensor_order.is_some()),
            ("--slice", self.slice.is_some()),
            ("--slices", self.slices.is_some()),
            ("--block", self.block),
            ("--voxels", self.voxels.is_some()),
            ("--mask", self.mask.is_some()),
            ("--scale", self.scale.is_some()),
            ("--norm", self.norm.is_some()),
            ("--min-amplitude", self.min_amplitude.is_some()),
            ("--perspective", self.perspective),
            ("--orientation", self.orientation.is_some()),
            ("--labels", self.labels),
            ("--underlay", self.underlay.is_some()),
            ("--underlay-range", self.underlay_range.is_some()),
            ("--underlay-plane", self.underlay_plane.is_some()),
            ("--views", self.views.is_some()),
            ("--lightbox", self.lightbox.is_some()),
            ("--peak-values", self.peak_values.is_some()),
            ("--peaks-color", self.peaks_color.is_some()),
            ("--peaks-norm", self.peaks_norm.is_some()),
            ("--peaks-scale", self.peaks_scale.is_some()),
            ("--peaks-width", self.peaks_width.is_some()),
            ("--peaks-frame", self.peaks_frame.is_some()),
        ];
        given.iter().find(|(_, on)| *on).map(|(name, _)| *name)
    }

    /// The flags as the library's volume request.
    pub fn request(&self) -> VolumeRequest {
        VolumeRequest {
            basis: self.basis.clone(),
            force_basis: self.force_basis,
            frame: self.frame.clone(),
            legacy: self.legacy.then_some(true),
            lmax: self.lmax,
            order: self.order,
            nonsymmetric: self.nonsymmetric,
            tensor_order: self.tensor_order.clone(),
            slice: self.slice.clone(),
            slices: self.slices.clone(),
            block: self.block,
            voxels: self.voxels.clone(),
            mask: self.mask.clone().map(ImageSource::File),
            scale: self.scale,
            norm: self.norm.clone(),
            min_amplitude: self.min_amplitude,
            perspective: self.perspective,
            orientation: self.orientation.clone(),
            glyph: self.glyph.clone(),
            underlay: self.underlay.clone().map(ImageSource::File),
            underlay_range: self.underlay_range.clone(),
            underlay_plane: self.underlay_plane.clone(),
            views: self.views.clone(),
            lightbox: self.lightbox,
            peaks: self.peaks.clone().map(ImageSource::File),
            peak_values: self.peak_values.clone(),
            peaks_color: self.peaks_color.clone(),
            peaks_norm: self.peaks_norm.clone(),
            peaks_scale: self.peaks_scale,
            peaks_width: self.peaks_width,
            peaks_frame: self.peaks_frame.clone(),
            tracks: self.tracks.clone().map(ImageSource::File),
            tracks_color: self.tracks_color.clone(),
            tracks_radius: self.tracks_radius,
            tracks_style: self.tracks_style.clone(),
            tracks_max: self.tracks_max,
            slab: self.slab,
        }
    }

    /// Whether --views or --lightbox asks for a montage.
    pub fn is_montage(&self) -> bool {
        self.views.is_some() || self.lightbox.is_some()
    }

    /// The figure of the volume input at the size `image`, reported on stderr: one view
    /// (with its underlay) or a montage's panels.
    pub fn figure(&self, image: ImageRequest) -> Result<VolumeFigure> {
        // Edge labels get a band free of glyphs (a lightbox's captions always do).
        let image = ImageRequest {
            keep_edges: self.labels,
            ..image
        };
        let request = self.request();
        let volume = self.read_volume(&request)?;
        report_basis(&volume);
        // The figure's notes hold the volume's.
        let figure = request.figure(volume, image)?;
        let (notes, warnings) = figure.messages();
        for note in notes {
            eprintln!("note: {}", spelled(note));
        }
        for warning in warnings {
            eprintln!("warning: {}", spelled(warning));
        }
        match &figure {
            VolumeFigure::View(view) => {
                let given = (self.peaks.is_some(), self.tracks.is_some());
                report(&view.scene, &view.volume.file, given);
                if let Some(underlay) = &view.underlay {
                    let volume = &underlay.volume;
                    let (lo, hi) = volume.window();
                    eprintln!(
                        "underlay: {}: {} voxel(s) of {} channel(s), window {lo}:{hi}",
                        volume.file,
                        volume.dims.map(|n| n.to_string()).join("x"),
                        volume.channels
                    );
                }
            }
            VolumeFigure::Montage(montage) => {
                for panel in &montage.panels {
                    report(
                        panel,
                        &montage.file,
                        (self.peaks.is_some(), self.tracks.is_some()),
                    );
                }
            }
        }
        Ok(figure)
    }

    /// The volume of `--views` or `--lightbox` and its panels' options, in reading order,
    /// with the grid's columns, for the viewer (which builds each panel's scene, and
    /// builds it again when the panel's slice moves: [`panel_view`]).
    pub fn montage_panels(&self, image: ImageRequest) -> Result<(Volume, MontagePlan)> {
        let request = self.request();
        let volume = self.read_volume(&request)?;
        report_basis(&volume);
        let plan = request.montage_plan(&volume, image)?;
        for note in volume.notes.iter().chain(&plan.notes) {
            eprintln!("note: {}", spelled(note));
        }
        Ok((volume, plan))
    }

    /// Sets every glyph set of a scene file to `--glyph`'s shape, if given.
    pub fn apply_shape(&self, scene: &mut Scene) -> Result<()> {
        match self.request().shape()? {
            Some(shape) => scene.set_shape(shape),
            None => Ok(()),
        }
    }

    /// The volume of --sh or --tensor, or, with --peaks alone, the stand-in of the
    /// peaks' grid.
    fn read_volume(&self, request: &VolumeRequest) -> Result<Volume> {
        if self.sh.is_none() && self.tensor.is_none() && self.peaks.is_some() {
            return request.peaks_grid();
        }
        let (input, path) = self.input()?;
        request.read_volume(input, path)
    }

    /// What --sh or --tensor says the file holds, and the file.
    fn input(&self) -> Result<(Coefficients, &Path)> {
        match (&self.sh, &self.tensor) {
            (Some(_), Some(_)) => Err(Error::conflict("--sh", Relation::Exclusive, "--tensor")),
            (Some(path), None) => Ok((Coefficients::Sh, path)),
            (None, Some(path)) => Ok((Coefficients::Tensor, path)),
            (None, None) => Err(Error::conflict(
                "this command",
                Relation::Requires,
                "a scene file, --sh or --tensor",
            )),
        }
    }
}

/// The scene of one montage panel (`options` from [`VolumeArgs::montage_panels`]),
/// reported with its warnings.
pub fn panel_view(volume: &Volume, options: &VolumeOptions) -> Result<VolumeScene> {
    let view = volume_scene(volume, options)?;
    for warning in view.report.warnings(&volume.file) {
        eprintln!("warning: {}", spelled(&warning));
    }
    let given = (options.peaks.is_some(), options.tracks.is_some());
    report(&view, &volume.file, given);
    Ok(view)
}

/// A library message with the settings it mentions spelled as flags.
fn spelled(text: &glyphcast::error::Message) -> String {
    text.spelled(&super::flags::spell)
}

/// The SH basis an SH volume is drawn in, with its variant, on a line of its own.
fn report_basis(volume: &Volume) {
    if let Some(basis) = volume.basis_summary() {
        eprintln!("SH basis: {}: {basis}", volume.file);
    }
}

/// One summary line of the glyphs (none for peaks alone: nothing was selected) and one
/// line of the peaks (the warnings are the figure's: `VolumeFigure::messages`).
fn report(view: &VolumeScene, file: &str, (peaks, tracks): (bool, bool)) {
    // The streamlines' segments are drawn in the peaks' set: counted with them.
    if let Some(drawn) = &view.peaks {
        let count = drawn.all().count();
        match (peaks, tracks) {
            (_, false) => eprintln!("peaks: {file}: {count} peaks drawn"),
            (false, true) => eprintln!("tracks: {count} segments drawn"),
            (true, true) => eprintln!("peaks and tracks: {count} peaks and segments drawn"),
        }
    }
    if view.report.selected == 0 {
        return;
    }
    let r = &view.report;
    let selection = match &view.block {
        Some(block) => format!("block {}", show_block(block)),
        None => {
            let slices: Vec<String> = view
                .regions
                .iter()
                .map(|r| format!("{}={}", ["i", "j", "k"][r.slice.voxel_axis()], r.index))
                .collect();
            format!("slice {}", slices.join(" "))
        }
    };
    eprintln!(
        "volume: {file}: {selection}: {} glyphs from {} voxels ({} masked out, {} not \
         finite, {} zero, {} below {})",
        r.drawn,
        r.selected,
        r.masked_out,
        r.non_finite,
        r.zero,
        r.below_min_amplitude,
        super::flags::flag(Setting::MinAmplitude)
    );
}

/// `--views` or `--lightbox` with a scene file: a montage is made of a volume's slices.
pub fn montage_needs_volume() -> Error {
    Error::conflict(
        "--views/--lightbox",
        Relation::Requires,
        "volume input (--sh/--tensor)",
    )
}

/// `--save-scene` with `--views` or `--lightbox`: a montage is several scenes.
pub fn save_scene_with_montage() -> Error {
    Error::conflict(
        "--save-scene",
        Relation::Excludes,
        "--views/--lightbox (it writes one scene)",
    )
}
