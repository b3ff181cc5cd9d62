//! Reading the DWI series and the optional brain mask: NIfTI (`.nii`, `.nii.gz`,
//! `.hdr`/`.img`, read by `io::nifti`) or MRtrix (`.mif`, `.mif.gz`, `.mih`), by the
//! file name.
//!
//! Both readers apply the stored scaling and return the voxels as f64 of shape
//! [x, y, z, t] whatever the stored type. A NIfTI header is kept as read, so that a NIfTI output can copy it (affine, voxel size, units); an MRtrix input
//! keeps its exact affine and its `dw_scheme`, and gets a NIfTI header built from the
//! affine ([`nifti_header_for`]).
use ndarray::{Array3, Array4, Axis, Ix3, Ix4};
use std::path::Path;

use crate::io::image::is_mrtrix;
use crate::io::mif::read_mif;
use crate::io::nifti::write::nifti_header_for;
use crate::io::nifti::{NiftiHeader, VoxelToWorld, read_nifti};
use glyphcast::{Error, Result};

/// A 4D diffusion-weighted series.
#[derive(Clone, Debug)]
pub struct Dwi {
    /// The path as given, for messages.
    pub file: String,
    /// The NIfTI header a NIfTI output copies: the file's own, or for an MRtrix input
    /// one built from its affine.
    pub header: NiftiHeader,
    /// Signal per voxel and volume, [x, y, z, volume].
    pub signal: Array4<f64>,
    /// The affine of an MRtrix input (a NIfTI one is derived from `header` when needed).
    pub mrtrix_affine: Option<VoxelToWorld>,
    /// An MRtrix input's `dw_scheme`: gx, gy, gz (scanner coordinates), b per volume.
    pub dw_scheme: Option<Vec<[f64; 4]>>,
}

impl Dwi {
    /// Spatial shape [x, y, z].
    pub fn spatial_shape(&self) -> [usize; 3] {
        let s = self.signal.shape();
        [s[0], s[1], s[2]]
    }

    /// Number of volumes (the fourth dimension): one per b-value and direction.
    pub fn volume_count(&self) -> usize {
        self.signal.shape()[3]
    }

    /// The voxel-to-world map: an MRtrix input's, or the NIfTI header's (sform, qform or
    /// pixdim; an error names the field when it is unusable).
    pub fn voxel_to_world(&self) -> Result<VoxelToWorld> {
        match self.mrtrix_affine {
            Some(map) => Ok(map),
            None => VoxelToWorld::from_header(&self.header, &self.file),
        }
    }
}

/// Reads a 4D NIfTI or MRtrix image; a file of any other dimensionality is an error
/// naming it.
pub fn read_dwi(path: &Path) -> Result<Dwi> {
    let file = path.display().to_string();
    let (header, data, mrtrix_affine, dw_scheme) = if is_mrtrix(path) {
        let image = read_mif(path)?;
        let header = nifti_header_for(&image.voxel_to_world);
        let scheme = image.header.dw_scheme.clone();
        let data = squeeze_past(image.data, 4);
        (header, data, Some(image.voxel_to_world), scheme)
    } else {
        let image = read_nifti(path)?;
        (image.header, image.data, None, None)
    };
    if data.ndim() != 4 {
        return Err(Error::input(
            path.display().to_string(),
            "dim",
            format!(
                "expected a 4D volume (x, y, z, volumes), got {}D {}",
                data.ndim(),
                shape_text(data.shape())
            ),
        ));
    }
    let signal = data
        .into_dimensionality::<Ix4>()
        .map_err(|err| Error::io(path, err))?;
    Ok(Dwi {
        file,
        header,
        signal,
        mrtrix_affine,
        dw_scheme,
    })
}

/// Drops trailing axes of length 1 beyond `rank` (an MRtrix header may list them).
fn squeeze_past(mut data: ndarray::ArrayD<f64>, rank: usize) -> ndarray::ArrayD<f64> {
    while data.ndim() > rank && data.shape().last() == Some(&1) {
        let last = Axis(data.ndim() - 1);
        data = data.index_axis_move(last, 0);
    }
    data
}

/// Reads a mask of spatial shape `shape`: a 3D volume (or 4D with one volume), where any
/// non-zero voxel is inside.
pub fn read_mask(
    path: &Path,
    shape: [usize; 3],
    map: &VoxelToWorld,
    dwi: &str,
) -> Result<Array3<bool>> {
    let file = path.display().to_string();
    let image = crate::io::image::read_image(path)?;
    let data = image.data;
    let dims = data.shape().to_vec();
    let spatial_ok = dims.len() >= 3 && dims[..3] == shape;
    if !spatial_ok || dims[3.min(dims.len())..].iter().any(|&d| d != 1) {
        return Err(Error::input(
            file,
            "dim",
            format!(
                "mask of shape {} does not match the spatial shape {} of {dwi}",
                shape_text(&dims),
                shape_text(&shape)
            ),
        ));
    }
    // The same grid in space, not only the same shape (float32 headers round).
    let tolerance = 1e-3 * map.voxel_sizes().min_element();
    if !image
        .voxel_to_world
        .affine
        .abs_diff_eq(map.affine, tolerance)
    {
        return Err(Error::input(
            file,
            "affine",
            format!(
                "the mask's voxel-to-world affine is not that of {dwi}: a mask of the same \
                 shape on another grid would keep other voxels"
            ),
        ));
    }
    let mut data = data;
    while data.ndim() > 3 {
        data = data.index_axis_move(Axis(3), 0);
    }
    let data = data
        .into_dimensionality::<Ix3>()
        .map_err(|err| Error::io(path, err))?;
    // Nonzero values, NaN counting as zero, as every mask glyphcast reads.
    Ok(data.mapv(|v| v != 0.0 && !v.is_nan()))
}

fn shape_text(shape: &[usize]) -> String {
    shape
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("x")
}
