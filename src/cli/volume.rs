//! Volume input for `glyphcast render`: a slice of a 4D NIfTI or MRtrix volume of SH coefficients
//! (`--sh`) or Cartesian tensor coefficients (`--tensor`) becomes the scene; the work is
//! in `glyphcast::volume`, this file turns flags into its options and reports what was
//! left out.
//!
//! `--basis` has no default of its own: it is what the file records (`glyphcast fit`'s
//! description; tournier07 for MRtrix images, MRtrix's only basis), and without a record
//! it must be given, since guessing wrong draws plausible but wrong glyphs
//! (`glyphcast::volume::resolve_basis`).
use clap::Args;
use glyphcast::fit::parse_basis;
use glyphcast::glyph::ellipsoid::ELLIPSOID_LAYOUT;
use glyphcast::glyph::{GlyphShape, Symmetry, TensorLayout};
use glyphcast::io::image::{Image, read_image};
use glyphcast::render::underlay::Underlay;
use glyphcast::scene::GlyphKind;
use glyphcast::scene::{Scene, ShBasis};
use glyphcast::volume::{
    ImageRequest, Slice, SliceRegion, ViewProjection, Volume, VolumeKind, VolumeOptions,
    VolumeScene, load_mask, load_underlay, resolve_basis, view_underlay, volume_scene,
};
use glyphcast::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Flags that make a scene file unnecessary.
pub const VOLUME_FLAGS: [&str; 2] = ["sh", "tensor"];

#[derive(Args)]
pub struct VolumeArgs {
    /// 4D image of SH coefficients, [x, y, z, (L+1)(L+2)/2] for an even band L <= 12:
    /// NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz, .mih); see --frame.
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub sh: Option<PathBuf>,
    /// SH basis of --sh: tournier07 or descoteaux07 (with --legacy for the legacy
    /// variant), or mrtrix (= tournier07, dwi2fod's output), dipy (= descoteaux07
    /// legacy, DIPY's default) or dipy-new (= descoteaux07). Default: the basis the file
    /// records (glyphcast fit writes it), tournier07 for MRtrix images without a record.
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
    /// 4D NIfTI or MRtrix image of Cartesian tensor coefficients in the scene format's
    /// order (order 2: xx, xy, xz, yy, yz, zz).
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub tensor: Option<PathBuf>,
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
    /// Voxel index ranges i0:i1,j0:j1,k0:k1 (end exclusive, ends optional), intersected
    /// with the slice.
    #[arg(long, value_name = "RANGES", help_heading = "Volume input")]
    pub voxels: Option<String>,
    /// 3D NIfTI or MRtrix mask of the volume's shape: glyphs only where it is nonzero.
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub mask: Option<PathBuf>,
    /// World radius of the largest glyph (default: 0.45 times the smallest voxel size).
    #[arg(long, value_name = "S", help_heading = "Volume input")]
    pub scale: Option<f64>,
    /// Glyph sizes: global (one factor for all), per-glyph (all the same size) or none
    /// (amplitude times --scale). Default global.
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
    /// Anatomical underlay drawn as a plane through each slice, in the glyphs' depth
    /// buffer: a 3D NIfTI or MRtrix image (FA, T1) or an RGB one [x, y, z, 3]
    /// (colour-FA), sampled trilinearly through its own affine (the grids may differ).
    #[arg(long, value_name = "IMAGE", help_heading = "Underlay")]
    pub underlay: Option<PathBuf>,
    /// The underlay's window: LOW is drawn black, HIGH white (each RGB channel alike).
    /// Default: the 2nd to 98th percentile of its finite values.
    #[arg(long, value_name = "LOW:HIGH", help_heading = "Underlay")]
    pub underlay_range: Option<String>,
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
    /// Also write the scene that is rendered as a scene file (with the image, all or
    /// nothing).
    #[arg(long, value_name = "FILE")]
    pub save_scene: Option<PathBuf>,
}

impl VolumeArgs {
    pub fn is_given(&self) -> bool {
        self.sh.is_some() || self.tensor.is_some()
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
            ("--slice", self.slice.is_some()),
            ("--slices", self.slices.is_some()),
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
            ("--views", self.views.is_some()),
            ("--lightbox", self.lightbox.is_some()),
        ];
        given.iter().find(|(_, on)| *on).map(|(name, _)| *name)
    }

    /// The scene of the volume view and its underlay (`--underlay`), if any.
    pub fn scene_with_underlay(&self, image: ImageRequest) -> Result<(Scene, Option<Underlay>)> {
        let (volume, _, view) = self.view(image)?;
        let underlay = self.underlay(&volume, &view.regions)?;
        Ok((view.scene, underlay))
    }

    /// `--underlay-range`, parsed (usage errors name the flag).
    fn underlay_range(&self) -> Result<Option<(f64, f64)>> {
        let Some(text) = self.underlay_range.as_deref() else {
            return Ok(None);
        };
        if self.underlay.is_none() {
            return Err(Error::Usage(
                "--underlay-range needs --underlay (the image it windows)".into(),
            ));
        }
        let parsed = text.split_once(':').and_then(|(lo, hi)| {
            Some((
                lo.trim().parse::<f64>().ok()?,
                hi.trim().parse::<f64>().ok()?,
            ))
        });
        match parsed {
            Some((lo, hi)) if lo.is_finite() && hi.is_finite() && lo < hi => Ok(Some((lo, hi))),
            _ => Err(Error::Usage(format!(
                "--underlay-range: '{}' is not LOW:HIGH with finite numbers, LOW < HIGH",
                glyphcast::error::quoted(text)
            ))),
        }
    }

    /// The underlay of a view of `volume` with slices `regions` (`--underlay`), with its
    /// window (`--underlay-range`, else the 2nd to 98th percentile).
    pub fn underlay(&self, volume: &Volume, regions: &[SliceRegion]) -> Result<Option<Underlay>> {
        let range = self.underlay_range()?;
        let Some(path) = &self.underlay else {
            return Ok(None);
        };
        let (mut underlay, source) = load_underlay(path)?;
        if let Some((lo, hi)) = range {
            underlay.set_window(lo, hi).map_err(Error::into_usage)?;
        }
        let (lo, hi) = underlay.window();
        eprintln!(
            "underlay: {}: {} voxel(s) of {} channel(s), window {lo}:{hi}",
            underlay.file,
            underlay.dims.map(|n| n.to_string()).join("x"),
            underlay.channels
        );
        view_underlay(Arc::new(underlay), source, volume, regions).map(Some)
    }

    /// `--glyph`, if given; an unknown shape is a usage error.
    pub fn shape(&self) -> Result<Option<GlyphShape>> {
        let parse = |text: &str| match text {
            "polynomial" => Ok(GlyphShape::Polynomial),
            "ellipsoid" => Ok(GlyphShape::Ellipsoid),
            _ => Err(Error::Usage(format!(
                "--glyph: '{}' is not one of polynomial, ellipsoid",
                glyphcast::error::quoted(text)
            ))),
        };
        self.glyph.as_deref().map(parse).transpose()
    }

    /// Sets every glyph set of a scene file to `--glyph`'s shape: a usage error naming
    /// the set when it is not an order-2 symmetric tensor set.
    pub fn apply_shape(&self, scene: &mut Scene) -> Result<()> {
        let Some(shape) = self.shape()? else {
            return Ok(());
        };
        for (index, set) in scene.glyph_sets.iter_mut().enumerate() {
            if shape == GlyphShape::Ellipsoid && set.kind != GlyphKind::Tensor(ELLIPSOID_LAYOUT) {
                return Err(Error::Usage(format!(
                    "--glyph ellipsoid draws symmetric tensors of order 2 (DTI), and glyph \
                     set {index} is a {}",
                    set.kind
                )));
            }
            set.shape = shape;
        }
        Ok(())
    }

    /// The volume, the options its view was made with and the view (reported on stderr):
    /// what the viewer needs to move the slice later.
    pub fn view(&self, image: ImageRequest) -> Result<(Volume, VolumeOptions, VolumeScene)> {
        self.underlay_range()?;
        if self.is_montage() {
            return Err(Error::Usage(
                "--views and --lightbox make several panels, not one view".into(),
            ));
        }
        let (volume, mut options) = self.load(image)?;
        self.slice_in_voxels(&mut options, &volume)?;
        let view = volume_scene(&volume, &options)?;
        report(&view, &volume.file);
        Ok((volume, options, view))
    }

    /// Whether --views or --lightbox asks for a montage.
    pub fn is_montage(&self) -> bool {
        self.views.is_some() || self.lightbox.is_some()
    }

    /// The scenes of the panels of `--views` or `--lightbox`, in reading order, and the
    /// number of columns of their grid (one row for --views).
    pub fn montage(&self, image: ImageRequest) -> Result<(Vec<Scene>, usize)> {
        let (volume, panels, columns) = self.montage_panels(image)?;
        let mut scenes = Vec::with_capacity(panels.len());
        for options in &panels {
            scenes.push(panel_view(&volume, options)?.scene);
        }
        Ok((scenes, columns))
    }

    /// The volume of `--views` or `--lightbox`, each panel's options (its slice, in voxel
    /// axes) in reading order, and the number of columns of their grid.
    pub fn montage_panels(
        &self,
        image: ImageRequest,
    ) -> Result<(Volume, Vec<VolumeOptions>, usize)> {
        let panels = match (&self.views, self.lightbox) {
            (Some(_), Some(_)) => {
                return Err(Error::Usage(
                    "give either --views or --lightbox, not both".into(),
                ));
            }
            (Some(views), None) => parse_views(views).map_err(Error::into_usage)?,
            (None, Some(count)) => {
                if self.slices.is_some() {
                    return Err(Error::Usage(
                        "--lightbox takes --slice, not --slices".into(),
                    ));
                }
                if count == 0 || count > MAX_PANELS {
                    return Err(Error::Usage(format!(
                        "--lightbox {count}: must be 1 to {MAX_PANELS} slices"
                    )));
                }
                Vec::new()
            }
            (None, None) => return Err(Error::Usage("no --views or --lightbox".into())),
        };
        if self.underlay.is_some() {
            return Err(Error::Usage(
                "--underlay draws on one view's planes: not with --views or --lightbox".into(),
            ));
        }
        if self.slices.is_some() || (self.views.is_some() && self.slice.is_some()) {
            return Err(Error::Usage(
                "--views names each panel's slice: give no --slice or --slices with it".into(),
            ));
        }
        let (volume, options) = self.load(image)?;
        let panels = match self.lightbox {
            Some(count) => self.lightbox_slices(&volume, &options, count)?,
            None => panels,
        };
        let mut panel_options = Vec::with_capacity(panels.len());
        for slice in &panels {
            let mut options = options.clone();
            options.slice = *slice;
            self.slice_in_voxels(&mut options, &volume)?;
            panel_options.push(options);
        }
        let columns = match self.lightbox {
            Some(count) => (count as f64).sqrt().ceil() as usize,
            None => panel_options.len(),
        };
        Ok((volume, panel_options, columns))
    }

    /// `count` slices of the --slice plane, evenly spaced: slice k at the centre of the
    /// k-th of `count` equal parts of the axis, floor((k + 1/2) n / count).
    fn lightbox_slices(
        &self,
        volume: &Volume,
        options: &VolumeOptions,
        count: usize,
    ) -> Result<Vec<Slice>> {
        let mut plane = options.clone();
        self.slice_in_voxels(&mut plane, volume)?;
        let axis = plane.slice.axis;
        let length = volume.dims[axis.voxel_axis()];
        if count > length {
            return Err(Error::Usage(format!(
                "--lightbox {count}: the {} plane has {length} slices in {}",
                axis.name(),
                volume.file
            )));
        }
        Ok((0..count)
            .map(|k| Slice {
                axis: options.slice.axis,
                index: Some(((2 * k + 1) * length) / (2 * count)),
            })
            .collect())
    }

    /// The volume and the options of the flags (mask read), before the slice is turned
    /// into voxel axes.
    fn load(&self, image: ImageRequest) -> Result<(Volume, VolumeOptions)> {
        let path = self.input().map_err(Error::into_usage)?;
        let mut options = self.options(image).map_err(Error::into_usage)?;
        let frame = self
            .frame
            .as_deref()
            .map(|text| {
                text.parse()
                    .map_err(|err| Error::Usage(format!("--frame: {err}")))
            })
            .transpose()?;
        let given_basis = self.given_basis()?;
        let file = read_image(path)?;
        let kind = self.kind(&file, given_basis)?;
        if options.shape == GlyphShape::Ellipsoid && kind != VolumeKind::Tensor(ELLIPSOID_LAYOUT) {
            return Err(Error::Usage(format!(
                "--glyph ellipsoid draws order-2 symmetric tensors (DTI: --tensor with \
                 --order 2), not {}",
                file.file
            )));
        }
        let mut volume = Volume::from_image(file, kind)?;
        volume.frame = frame.unwrap_or(volume.frame);
        options.mask = self.mask.as_deref().map(load_mask).transpose()?;
        Ok((volume, options))
    }

    /// Turns the world plane `--slice` names into the voxel axis closest to it, with a
    /// note when that is not the axis of the same name (a volume not stored axially), and
    /// an error in the plane's terms when the index is outside that axis.
    fn slice_in_voxels(&self, options: &mut VolumeOptions, volume: &Volume) -> Result<()> {
        let named = options.slice;
        let axis = named
            .axis
            .world_plane_in_voxels(volume.voxel_to_world.linear());
        options.slice.axis = axis;
        if axis == named.axis || options.slices.is_some() {
            return Ok(());
        }
        let voxel = axis.voxel_axis();
        let (letter, length) = (["i", "j", "k"][voxel], volume.dims[voxel]);
        if let Some(index) = named.index
            && index >= length
        {
            return Err(Error::input(
                &volume.file,
                format!("dim[{}]", voxel + 1),
                format!(
                    "--slice {named}: the {} plane is the slice of constant {letter} in this \
                     volume, which has {length} voxels along {letter} (0..={})",
                    named.axis.name(),
                    length.saturating_sub(1)
                ),
            ));
        }
        eprintln!(
            "note: {}: the {} plane is the slice of constant {letter} in this volume",
            volume.file,
            named.axis.name(),
        );
        Ok(())
    }

    /// The volume's file, once the flags are checked to fit --sh or --tensor.
    fn input(&self) -> Result<&Path> {
        let misplaced = |flag: &str, input: &str| {
            Err(Error::Invalid(format!(
                "{flag} applies to {input} input only"
            )))
        };
        match (&self.sh, &self.tensor) {
            (Some(_), Some(_)) => Err(Error::Invalid(
                "give either --sh or --tensor, not both".into(),
            )),
            (Some(path), None) => {
                if self.order.is_some() {
                    return misplaced("--order", "--tensor");
                }
                if self.nonsymmetric {
                    return misplaced("--nonsymmetric", "--tensor");
                }
                Ok(path)
            }
            (None, Some(path)) => {
                for (flag, given) in [
                    ("--basis", self.basis.is_some()),
                    ("--force-basis", self.force_basis),
                    ("--legacy", self.legacy),
                    ("--lmax", self.lmax.is_some()),
                ] {
                    if given {
                        return misplaced(flag, "--sh");
                    }
                }
                self.tensor_order()?;
                Ok(path)
            }
            (None, None) => Err(Error::Invalid("give a scene file, --sh or --tensor".into())),
        }
    }

    /// What the file holds: for --sh the basis from `--basis` and the file's record
    /// (`resolve_basis`), for --tensor the layout from --order and --nonsymmetric.
    fn kind(&self, file: &Image, given_basis: Option<(ShBasis, bool)>) -> Result<VolumeKind> {
        if self.sh.is_some() {
            let (basis, legacy) = resolve_basis(file, given_basis, self.force_basis)?;
            return Ok(VolumeKind::Sh { basis, legacy });
        }
        let order = self.tensor_order()?;
        let symmetry = if self.nonsymmetric {
            Symmetry::NonSymmetric
        } else {
            Symmetry::Symmetric
        };
        Ok(VolumeKind::Tensor(TensorLayout { order, symmetry }))
    }

    /// `--order`, which --tensor needs.
    fn tensor_order(&self) -> Result<u32> {
        self.order.ok_or_else(|| {
            Error::Invalid("--tensor needs --order N (the tensor order of the file)".into())
        })
    }

    /// `--basis` with `--legacy` (aliases name both; see `fit::parse_basis`), if given.
    fn given_basis(&self) -> Result<Option<(ShBasis, bool)>> {
        match self.basis.as_deref() {
            Some(name) => parse_basis(name, self.legacy).map(Some),
            None if self.legacy => Err(Error::Usage(
                "--legacy qualifies --basis: give --basis too".into(),
            )),
            None if self.force_basis => Err(Error::Usage(
                "--force-basis needs --basis (the basis to force)".into(),
            )),
            None => Ok(None),
        }
    }

    /// Everything but the mask, which is read after the volume.
    fn options(&self, image: ImageRequest) -> Result<VolumeOptions> {
        if self.slice.is_some() && self.slices.is_some() {
            return Err(Error::Invalid(
                "give either --slice or --slices, not both".into(),
            ));
        }
        Ok(VolumeOptions {
            slices: self.slices.as_deref().map(str::parse).transpose()?,
            slice: self
                .slice
                .as_deref()
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            voxels: self
                .voxels
                .as_deref()
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            mask: None,
            shape: self.shape()?.unwrap_or_default(),
            scale: self.scale,
            norm: self
                .norm
                .as_deref()
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            min_amplitude: self.min_amplitude.unwrap_or(0.0),
            lmax: self.lmax,
            projection: if self.perspective {
                ViewProjection::Perspective
            } else {
                ViewProjection::Orthographic
            },
            orientation: self
                .orientation
                .as_deref()
                .map(str::parse)
                .transpose()?
                .unwrap_or_default(),
            image,
        })
    }
}

/// The most panels of a montage.
pub const MAX_PANELS: usize = 64;

/// `--views`: axial, coronal and sagittal (each optionally :INDEX), comma separated, each
/// at most once.
pub fn parse_views(text: &str) -> Result<Vec<Slice>> {
    let mut slices: Vec<Slice> = Vec::new();
    for item in text.split(',') {
        let slice: Slice = item.trim().parse().map_err(|_| {
            Error::Invalid(format!(
                "--views '{text}': '{item}' is not axial, coronal or sagittal (optionally \
                 :INDEX)"
            ))
        })?;
        if slices.iter().any(|s| s.axis == slice.axis) {
            return Err(Error::Invalid(format!(
                "--views '{text}': {} is listed twice",
                slice.axis.name()
            )));
        }
        slices.push(slice);
    }
    Ok(slices)
}

/// The view of one montage panel (`options` from [`VolumeArgs::montage_panels`]),
/// reported.
pub fn panel_view(volume: &Volume, options: &VolumeOptions) -> Result<VolumeScene> {
    let view = volume_scene(volume, options)?;
    report(&view, &volume.file);
    Ok(view)
}

/// One summary line, and a warning when voxels were left out for bad values.
fn report(view: &VolumeScene, file: &str) {
    let r = &view.report;
    if r.non_finite > 0 {
        eprintln!(
            "warning: {file}: {} voxel(s) with NaN or infinite coefficients left out",
            r.non_finite
        );
    }
    let slices: Vec<String> = view
        .regions
        .iter()
        .map(|r| format!("{}={}", ["i", "j", "k"][r.slice.voxel_axis()], r.index))
        .collect();
    eprintln!(
        "volume: {file}: slice {}: {} glyphs from {} voxels ({} masked out, {} not \
         finite, {} zero, {} below --min-amplitude)",
        slices.join(" "),
        r.drawn,
        r.selected,
        r.masked_out,
        r.non_finite,
        r.zero,
        r.below_min_amplitude
    );
}
