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
use glyphcast::io::image::read_image;
use glyphcast::scene::Scene;
use glyphcast::volume::{
    ImageRequest, Volume, VolumeOptions, VolumeRequest, VolumeScene, load_mask,
};
use glyphcast::{Error, Result};
use std::path::{Path, PathBuf};

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
    /// optionally :INDEX along that voxel axis or :mid (default: the middle axial slice).
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
    /// Write the anatomical directions (L/R, A/P, S/I) at the image's edges.
    #[arg(long, help_heading = "Volume input")]
    pub labels: bool,
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
        ];
        given.iter().find(|(_, on)| *on).map(|(name, _)| *name)
    }

    /// The scene of the volume view; `image` is the size asked for with --width/--height.
    pub fn scene(&self, image: ImageRequest) -> Result<Scene> {
        Ok(self.view(image)?.2.scene)
    }

    /// The flags as the library's volume request (shared with the Python module).
    pub fn request(&self) -> VolumeRequest {
        VolumeRequest {
            basis: self.basis.clone(),
            force_basis: self.force_basis,
            frame: self.frame.clone(),
            legacy: self.legacy,
            lmax: self.lmax,
            order: self.order,
            nonsymmetric: self.nonsymmetric,
            slice: self.slice.clone(),
            slices: self.slices.clone(),
            voxels: self.voxels.clone(),
            scale: self.scale,
            norm: self.norm.clone(),
            min_amplitude: self.min_amplitude,
            perspective: self.perspective,
            orientation: self.orientation.clone(),
        }
    }

    /// The volume, the options its view was made with and the view (reported on stderr):
    /// what the viewer needs to move the slice later.
    pub fn view(&self, image: ImageRequest) -> Result<(Volume, VolumeOptions, VolumeScene)> {
        let request = self.request();
        let path = self.input().map_err(Error::into_usage)?;
        let mut options = request.options(image).map_err(Error::into_usage)?;
        request.frame()?;
        if self.sh.is_some() {
            request.given_basis()?;
        }
        let file = read_image(path)?;
        let kind = if self.sh.is_some() {
            request.sh_kind(Some(&file))?
        } else {
            request.tensor_kind()?
        };
        let volume = Volume::from_image(file, kind)?;
        options.mask = self.mask.as_deref().map(load_mask).transpose()?;
        let view = request.view(volume, options)?;
        if let Some(note) = &view.note {
            eprintln!("note: {note}");
        }
        report(&view.scene, &view.volume.file);
        Ok((view.volume, view.options, view.scene))
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
                self.request().tensor_order()?;
                Ok(path)
            }
            (None, None) => Err(Error::Invalid("give a scene file, --sh or --tensor".into())),
        }
    }
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
