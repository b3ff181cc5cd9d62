//! The input files of a fit, read and checked against each other.
use ndarray::Array3;
use std::path::PathBuf;

use super::dwi::{Dwi, read_dwi, read_mask};
use super::gradients::GradientTable;
use crate::Result;

/// Where the inputs come from.
#[derive(Clone, Debug)]
pub struct FitFiles {
    pub dwi: PathBuf,
    pub bval: PathBuf,
    pub bvec: PathBuf,
    pub mask: Option<PathBuf>,
}

/// The DWI series, its gradient table and the optional mask, mutually consistent: one
/// b-value and direction per volume, a mask of the DWI's spatial shape.
#[derive(Clone, Debug)]
pub struct FitInputs {
    pub files: FitFiles,
    pub dwi: Dwi,
    pub gradients: GradientTable,
    pub mask: Option<Array3<bool>>,
}

impl FitInputs {
    pub fn load(files: FitFiles) -> Result<Self> {
        let dwi = read_dwi(&files.dwi)?;
        let name = files.dwi.display().to_string();
        let gradients = GradientTable::read(&files.bval, &files.bvec, dwi.volume_count(), &name)?;
        let mask = match &files.mask {
            Some(path) => Some(read_mask(path, dwi.spatial_shape(), &name)?),
            None => None,
        };
        Ok(Self {
            files,
            dwi,
            gradients,
            mask,
        })
    }

    /// Whether voxel (x, y, z) is fitted (inside the mask, or every voxel without one).
    pub fn in_mask(&self, x: usize, y: usize, z: usize) -> bool {
        self.mask.as_ref().is_none_or(|m| m[[x, y, z]])
    }

    /// Number of voxels the fit visits.
    pub fn voxel_count(&self) -> usize {
        match &self.mask {
            Some(mask) => mask.iter().filter(|&&v| v).count(),
            None => self.dwi.spatial_shape().iter().product(),
        }
    }
}
