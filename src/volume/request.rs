//! A volume view as the front ends ask for it: the CLI's volume flags and the Python
//! module's keyword arguments, as text and numbers, turned into the volume's kind and
//! [`VolumeOptions`] with one set of defaults and messages (which name the CLI's flags,
//! mirrored by the Python keywords), and the view made from them.
use super::build::{VolumeOptions, VolumeScene, volume_scene};
use super::framing::{ImageRequest, ViewProjection};
use super::input::{CoefficientFrame, Volume, VolumeKind};
use super::recorded::resolve_basis;
use crate::fit::parse_basis;
use crate::glyph::{Symmetry, TensorLayout};
use crate::io::image::Image;
use crate::scene::ShBasis;
use crate::{Error, Result};

/// The volume options, unparsed; `None` (or `false`) is the default.
#[derive(Clone, Debug, Default)]
pub struct VolumeRequest {
    /// `--basis`: tournier07, descoteaux07, mrtrix, dipy or dipy-new.
    pub basis: Option<String>,
    /// `--force-basis`: `basis` even where the file records another.
    pub force_basis: bool,
    /// `--frame`: voxel or world.
    pub frame: Option<String>,
    /// `--legacy`: the legacy variant of `basis`.
    pub legacy: bool,
    /// `--lmax`: draw SH bands up to this one.
    pub lmax: Option<u32>,
    /// `--order`: the tensor order of a tensor volume.
    pub order: Option<u32>,
    /// `--nonsymmetric`: a tensor volume holds all 3^N entries.
    pub nonsymmetric: bool,
    /// `--slice`: AXIS[:INDEX].
    pub slice: Option<String>,
    /// `--slices`: I,J,K or mid.
    pub slices: Option<String>,
    /// `--voxels`: i0:i1,j0:j1,k0:k1.
    pub voxels: Option<String>,
    /// `--scale`: world radius of the largest glyph.
    pub scale: Option<f64>,
    /// `--norm`: global, per-glyph or none.
    pub norm: Option<String>,
    /// `--min-amplitude`: leave out glyphs below this largest radius.
    pub min_amplitude: Option<f64>,
    /// `--perspective`: a perspective camera.
    pub perspective: bool,
    /// `--orientation`: radiological or neurological.
    pub orientation: Option<String>,
}

/// A volume's view: the scene and what it was made from.
pub struct VolumeView {
    /// The volume, in the frame asked for.
    pub volume: Volume,
    /// The options the view was made with (the slice in voxel axes).
    pub options: VolumeOptions,
    /// The scene and its report.
    pub scene: VolumeScene,
    /// A note for the user: the world plane asked for is another voxel axis.
    pub note: Option<String>,
}

impl VolumeRequest {
    /// Everything but the mask, which the caller reads.
    pub fn options(&self, image: ImageRequest) -> Result<VolumeOptions> {
        if self.slice.is_some() && self.slices.is_some() {
            return Err(Error::Invalid(
                "give either --slice or --slices, not both".into(),
            ));
        }
        Ok(VolumeOptions {
            slices: self.slices.as_deref().map(str::parse).transpose()?,
            slice: parse_or_default(self.slice.as_deref())?,
            voxels: parse_or_default(self.voxels.as_deref())?,
            mask: None,
            scale: self.scale,
            norm: parse_or_default(self.norm.as_deref())?,
            min_amplitude: self.min_amplitude.unwrap_or(0.0),
            lmax: self.lmax,
            projection: if self.perspective {
                ViewProjection::Perspective
            } else {
                ViewProjection::Orthographic
            },
            orientation: parse_or_default(self.orientation.as_deref())?,
            shape: Default::default(),
            image,
        })
    }

    /// `--frame`, if given (a usage error when it is not voxel or world).
    pub fn frame(&self) -> Result<Option<CoefficientFrame>> {
        self.frame
            .as_deref()
            .map(|text| {
                text.parse()
                    .map_err(|err| Error::Usage(format!("--frame: {err}")))
            })
            .transpose()
    }

    /// `--basis` with `--legacy` (aliases name both; see `fit::parse_basis`), if given.
    pub fn given_basis(&self) -> Result<Option<(ShBasis, bool)>> {
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

    /// An SH volume's kind: the basis from `--basis` and what `file` records
    /// ([`resolve_basis`]); without a file (coefficients from memory) `--basis` is needed.
    pub fn sh_kind(&self, file: Option<&Image>) -> Result<VolumeKind> {
        let given = self.given_basis()?;
        let (basis, legacy) = match file {
            Some(file) => resolve_basis(file, given, self.force_basis)?,
            None => given.ok_or_else(|| {
                Error::Usage("SH coefficients without a file need --basis".into())
            })?,
        };
        Ok(VolumeKind::Sh { basis, legacy })
    }

    /// A tensor volume's kind, from `--order` and `--nonsymmetric`.
    pub fn tensor_kind(&self) -> Result<VolumeKind> {
        let order = self.tensor_order()?;
        let symmetry = if self.nonsymmetric {
            Symmetry::NonSymmetric
        } else {
            Symmetry::Symmetric
        };
        Ok(VolumeKind::Tensor(TensorLayout { order, symmetry }))
    }

    /// `--order`, which a tensor volume needs.
    pub fn tensor_order(&self) -> Result<u32> {
        self.order.ok_or_else(|| {
            Error::Invalid("--tensor needs --order N (the tensor order of the file)".into())
        })
    }

    /// The view of `volume` with `options` (from [`VolumeRequest::options`], with the
    /// caller's mask): the volume in the frame `--frame` asks for, the slice's world
    /// plane turned into the voxel axis closest to it, and the scene.
    pub fn view(&self, mut volume: Volume, mut options: VolumeOptions) -> Result<VolumeView> {
        volume.frame = self.frame()?.unwrap_or(volume.frame);
        let note = slice_in_voxels(&mut options, &volume)?;
        let scene = volume_scene(&volume, &options)?;
        Ok(VolumeView {
            volume,
            options,
            scene,
            note,
        })
    }
}

fn parse_or_default<T>(text: Option<&str>) -> Result<T>
where
    T: std::str::FromStr<Err = Error> + Default,
{
    Ok(text.map(str::parse).transpose()?.unwrap_or_default())
}

/// Turns the world plane `--slice` names into the voxel axis closest to it, with a note
/// when that is not the axis of the same name (a volume not stored axially), and an error
/// in the plane's terms when the index is outside that axis.
fn slice_in_voxels(options: &mut VolumeOptions, volume: &Volume) -> Result<Option<String>> {
    let named = options.slice;
    let axis = named
        .axis
        .world_plane_in_voxels(volume.voxel_to_world.linear());
    options.slice.axis = axis;
    if axis == named.axis || options.slices.is_some() {
        return Ok(None);
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
    Ok(Some(format!(
        "{}: the {} plane is the slice of constant {letter} in this volume",
        volume.file,
        named.axis.name(),
    )))
}
