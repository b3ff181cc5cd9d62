//! Reading the DWI series and the optional brain mask (NIfTI-1, `.nii` or `.nii.gz`).
//!
//! The `nifti` crate applies `scl_slope`/`scl_inter` and returns the voxels as an
//! ndarray of shape [x, y, z, t] whatever the stored type. The header is kept as read,
//! so that the output can copy it (affine, voxel size, units).
use ndarray::{Array3, Array4, Axis, Ix3, Ix4};
use nifti::{IntoNdArray, NiftiError, NiftiHeader, NiftiObject, ReaderOptions};
use std::path::Path;

use crate::{Error, Result};

/// A 4D diffusion-weighted series.
#[derive(Clone, Debug)]
pub struct Dwi {
    pub header: NiftiHeader,
    /// Signal per voxel and volume, [x, y, z, volume].
    pub signal: Array4<f64>,
}

impl Dwi {
    /// Spatial shape [x, y, z].
    pub fn spatial_shape(&self) -> [usize; 3] {
        let s = self.signal.shape();
        [s[0], s[1], s[2]]
    }

    pub fn volume_count(&self) -> usize {
        self.signal.shape()[3]
    }
}

/// Reads a 4D NIfTI; a file of any other dimensionality is an error naming it.
pub fn read_dwi(path: &Path) -> Result<Dwi> {
    let (header, data) = read_volume(path)?;
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
    Ok(Dwi { header, signal })
}

/// Reads a mask of spatial shape `shape`: a 3D volume (or 4D with one volume), where any
/// non-zero voxel is inside.
pub fn read_mask(path: &Path, shape: [usize; 3], dwi: &str) -> Result<Array3<bool>> {
    let file = path.display().to_string();
    let (_, data) = read_volume(path)?;
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
    let mut data = data;
    while data.ndim() > 3 {
        data = data.index_axis_move(Axis(3), 0);
    }
    let data = data
        .into_dimensionality::<Ix3>()
        .map_err(|err| Error::io(path, err))?;
    Ok(data.mapv(|v| v != 0.0))
}

fn read_volume(path: &Path) -> Result<(NiftiHeader, ndarray::ArrayD<f64>)> {
    let object = ReaderOptions::new()
        .read_file(path)
        .map_err(|err| nifti_error(path, err))?;
    let header = object.header().clone();
    let data = object
        .into_volume()
        .into_ndarray::<f64>()
        .map_err(|err| nifti_error(path, err))?;
    Ok((header, data))
}

/// The crate's `Display` of an I/O error is its `Debug` form; report the I/O error's own.
fn nifti_error(path: &Path, err: NiftiError) -> Error {
    match err {
        NiftiError::Io(io) => Error::io(path, io),
        other => Error::io(path, format!("not a readable NIfTI-1 file: {other}")),
    }
}

fn shape_text(shape: &[usize]) -> String {
    shape
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("x")
}
