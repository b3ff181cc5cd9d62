//! Volume input for `glyphcast render`: a slice of a 4D NIfTI or MRtrix volume of SH coefficients
//! (`--sh`) or Cartesian tensor coefficients (`--tensor`) becomes the scene; the work is
//! in `glyphcast::volume`, this file turns flags into its options and reports what was
//! left out.
//!
//! `--basis` has no default: a file does not say which SH basis it uses, and guessing
//! wrong draws plausible but wrong glyphs.
use clap::Args;
use glyphcast::fit::parse_basis;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::io::scene::{Scene, ShBasis};
use glyphcast::volume::{
    ImageRequest, ViewProjection, Volume, VolumeKind, VolumeOptions, VolumeScene, load_mask,
    load_volume, volume_scene,
};
use glyphcast::{Error, Result};
use std::path::{Path, PathBuf};

/// Flags that make a scene file unnecessary.
pub const VOLUME_FLAGS: [&str; 2] = ["sh", "tensor"];

#[derive(Args)]
pub struct VolumeArgs {
    /// 4D image of SH coefficients, [x, y, z, (L+1)(L+2)/2] for an even band L <= 12:
    /// NIfTI (.nii, .nii.gz) or MRtrix (.mif, .mif.gz, .mih), taken in voxel axes.
    #[arg(long, value_name = "IMAGE", help_heading = "Volume input")]
    pub sh: Option<PathBuf>,
    /// SH basis of --sh: tournier07 or descoteaux07 (with --legacy for the legacy
    /// variant), or mrtrix (= tournier07, dwi2fod's output), dipy (= descoteaux07
    /// legacy, DIPY's default) or dipy-new (= descoteaux07).
    #[arg(long, value_name = "BASIS", help_heading = "Volume input")]
    pub basis: Option<String>,
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
    /// Slice to draw: axial, coronal or sagittal (constant k, j or i), optionally :INDEX
    /// (default: the middle axial slice).
    #[arg(long, value_name = "AXIS[:INDEX]", help_heading = "Volume input")]
    pub slice: Option<String>,
    /// Three orthogonal slices at once instead of --slice: voxel indices I,J,K of the
    /// sagittal, coronal and axial slice, or mid (the middle of each); seen in perspective
    /// from anterior-superior-left.
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
        ];
        given.iter().find(|(_, on)| *on).map(|(name, _)| *name)
    }

    /// The scene of the volume view; `image` is the size asked for with --width/--height.
    pub fn scene(&self, image: ImageRequest) -> Result<Scene> {
        Ok(self.view(image)?.2.scene)
    }

    /// The volume, the options its view was made with and the view (reported on stderr):
    /// what the viewer needs to move the slice later.
    pub fn view(&self, image: ImageRequest) -> Result<(Volume, VolumeOptions, VolumeScene)> {
        let (path, kind) = self.input().map_err(Error::into_usage)?;
        let mut options = self.options(image).map_err(Error::into_usage)?;
        let volume = load_volume(path, kind)?;
        options.mask = self.mask.as_deref().map(load_mask).transpose()?;
        let view = volume_scene(&volume, &options)?;
        report(&view, &volume.file);
        Ok((volume, options, view))
    }

    fn input(&self) -> Result<(&Path, VolumeKind)> {
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
                let (basis, legacy) = self.basis()?;
                Ok((path, VolumeKind::Sh { basis, legacy }))
            }
            (None, Some(path)) => {
                for (flag, given) in [
                    ("--basis", self.basis.is_some()),
                    ("--legacy", self.legacy),
                    ("--lmax", self.lmax.is_some()),
                ] {
                    if given {
                        return misplaced(flag, "--sh");
                    }
                }
                let Some(order) = self.order else {
                    return Err(Error::Invalid(
                        "--tensor needs --order N (the tensor order of the file)".into(),
                    ));
                };
                let symmetry = if self.nonsymmetric {
                    Symmetry::NonSymmetric
                } else {
                    Symmetry::Symmetric
                };
                Ok((path, VolumeKind::Tensor(TensorLayout { order, symmetry })))
            }
            (None, None) => Err(Error::Invalid("give a scene file, --sh or --tensor".into())),
        }
    }

    /// The basis and its legacy flag (`--basis` aliases name both; see `fit::parse_basis`).
    fn basis(&self) -> Result<(ShBasis, bool)> {
        match self.basis.as_deref() {
            Some(name) => parse_basis(name, self.legacy),
            None => Err(Error::Invalid(
                "--sh needs --basis tournier07, descoteaux07, mrtrix, dipy or dipy-new (a file does not say which)".into(),
            )),
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
            image,
        })
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
