//! NIfTI-1 input (.nii, .nii.gz, .hdr/.img) through the `nifti` crate: the voxel values
//! as f64 (with scl_slope/scl_inter applied by the crate), the shape, and the
//! voxel-to-world affine ([`affine`]).
//!
//! Every failure names the file: a file that cannot be opened is an [`Error::Io`], one
//! that opens but is not a readable NIfTI-1 image an [`Error::Input`] with the header
//! field at fault where there is one. The whole image is read into memory; volumes of
//! glyph data are small next to that (a 100^3 band-8 FOD is 360 MB as f64).
use std::path::Path;

use ::nifti::{IntoNdArray, NiftiError, NiftiHeader, NiftiObject, ReaderOptions};
use ndarray::ArrayD;

use crate::{Error, Result};

pub mod affine;

pub use affine::{AffineSource, VoxelToWorld};

/// One NIfTI-1 image in memory.
#[derive(Clone, Debug)]
pub struct NiftiImage {
    /// The path as given, for messages.
    pub file: String,
    pub header: NiftiHeader,
    /// Voxel values, shape [x, y, z, t, ...] (Fortran memory order, as the file stores it).
    pub data: ArrayD<f64>,
    pub voxel_to_world: VoxelToWorld,
}

impl NiftiImage {
    /// The shape with trailing dimensions of size 1 dropped down to `rank` entries, and a
    /// 1D or 2D image padded to 3 ([x, y] is [x, y, 1]).
    pub fn shape(&self, rank: usize) -> Vec<usize> {
        crate::io::image::trimmed_shape(self.data.shape(), rank)
    }
}

/// Reads `path` as a NIfTI-1 image (compressed if the name ends in .gz).
pub fn read_nifti(path: &Path) -> Result<NiftiImage> {
    let file = path.display().to_string();
    // Opening is checked first so that a missing file is reported as such, not as a
    // format problem.
    std::fs::File::open(path).map_err(|err| Error::io(path, err))?;
    let object = ReaderOptions::new()
        .read_file(path)
        .map_err(|err| format_error(&file, err))?;
    let header = object.header().clone();
    let voxel_to_world = VoxelToWorld::from_header(&header, &file)?;
    let data = object
        .into_volume()
        .into_ndarray::<f64>()
        .map_err(|err| format_error(&file, err))?;
    Ok(NiftiImage {
        file,
        header,
        data,
        voxel_to_world,
    })
}

/// A reader error as an input error naming the file and, where known, the field.
fn format_error(file: &str, err: NiftiError) -> Error {
    let (field, message) = match &err {
        NiftiError::InvalidFormat => (
            "magic",
            "not a NIfTI-1 file (the magic code is neither \"n+1\" nor \"ni1\")".to_string(),
        ),
        NiftiError::InconsistentDim(..) => ("dim", err.to_string()),
        NiftiError::UnsupportedDataType(t) => ("datatype", format!("unsupported data type {t:?}")),
        NiftiError::InvalidTypeConversion(from, _) => (
            "datatype",
            format!("{from:?} values cannot be read as numbers"),
        ),
        NiftiError::InvalidCode(name, code) => (*name, format!("invalid code {code}")),
        NiftiError::NoVolumeData | NiftiError::MissingVolumeFile(_) => (
            "data",
            "no voxel data (header only, or the .img file is missing)".to_string(),
        ),
        NiftiError::Io(io) => (
            "data",
            format!("not a readable NIfTI-1 file (truncated or corrupt?): {io}"),
        ),
        _ => ("data", err.to_string()),
    };
    Error::input(file, field, message)
}
