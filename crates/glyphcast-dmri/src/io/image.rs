//! Volumes from any supported file format, chosen by the file name: MRtrix (`.mif`,
//! `.mif.gz`, `.mih`, see `io::mif`) or else NIfTI-1 or NIfTI-2 (`io::nifti`). Both give the voxel
//! values as f64 indexed by the file's voxel axes and the voxel-to-world affine, so every
//! consumer (`--sh`, `--tensor`, `--mask`, the DWI of `fit`) takes either.
use std::path::Path;

use ndarray::ArrayD;

use crate::io::mif::{MifHeader, MifKind, read_mif};
use crate::io::nifti::{NiftiHeader, NiftiImage, VoxelToWorld, read_nifti};
use glyphcast::Result;

/// What the header said besides the geometry.
#[derive(Clone, Debug)]
pub enum ImageHeader {
    /// A NIfTI-1 or NIfTI-2 header.
    Nifti(Box<NiftiHeader>),
    /// An MRtrix header.
    Mrtrix(Box<MifHeader>),
}

/// One volume in memory.
#[derive(Clone, Debug)]
pub struct Image {
    /// The path as given, for messages.
    pub file: String,
    /// Voxel values, shape [x, y, z, t, ...].
    pub data: ArrayD<f64>,
    /// Voxel indices to world coordinates, whichever format the file is.
    pub voxel_to_world: VoxelToWorld,
    /// The format's own header, for the fields only it has (intent, `dw_scheme`, ...).
    pub header: ImageHeader,
}

/// Whether `path` names an MRtrix image (else it is read as NIfTI).
pub fn is_mrtrix(path: &Path) -> bool {
    MifKind::of(path).is_some()
}

/// Reads `path` as MRtrix or NIfTI, by its name.
pub fn read_image(path: &Path) -> Result<Image> {
    if is_mrtrix(path) {
        let image = read_mif(path)?;
        Ok(Image {
            file: image.file,
            data: image.data,
            voxel_to_world: image.voxel_to_world,
            header: ImageHeader::Mrtrix(Box::new(image.header)),
        })
    } else {
        let NiftiImage {
            file,
            header,
            data,
            voxel_to_world,
        } = read_nifti(path)?;
        Ok(Image {
            file,
            data,
            voxel_to_world,
            header: ImageHeader::Nifti(Box::new(header)),
        })
    }
}

impl Image {
    /// The shape with trailing dimensions of size 1 dropped down to `rank` entries, and a
    /// 1D or 2D image padded to 3 ([x, y] is [x, y, 1]).
    pub fn shape(&self, rank: usize) -> Vec<usize> {
        trimmed_shape(self.data.shape(), rank)
    }

    /// The free-text description the file carries: a NIfTI header's `descrip`, or an
    /// MRtrix header's `comments` lines joined by newlines. `None` when empty. glyphcast's
    /// `fit` records its model and SH basis here.
    pub fn description(&self) -> Option<String> {
        let text = match &self.header {
            ImageHeader::Nifti(header) => header.description(),
            ImageHeader::Mrtrix(header) => header
                .other
                .iter()
                .filter(|(key, _)| key == "comments")
                .map(|(_, value)| value.as_str())
                .collect::<Vec<_>>()
                .join("\n"),
        };
        let text = text.trim().to_string();
        (!text.is_empty()).then_some(text)
    }
}

/// `shape` with trailing 1s dropped down to `rank` entries and padded to 3 entries.
pub fn trimmed_shape(shape: &[usize], rank: usize) -> Vec<usize> {
    let mut shape = shape.to_vec();
    while shape.len() > rank && shape.last() == Some(&1) {
        shape.pop();
    }
    while shape.len() < 3 {
        shape.push(1);
    }
    shape
}
