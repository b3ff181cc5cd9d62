//! The input files of a fit, read and checked against each other.
use ndarray::Array3;
use std::path::PathBuf;

use super::dwi::{Dwi, read_dwi, read_mask};
use super::gradients::GradientTable;
use crate::io::image::is_mrtrix;
use crate::setting::DmriSetting;
use glyphcast::{Error, Result};

/// Where the inputs come from. Without `bval` and `bvec` the gradient table is the
/// DWI's own (`dw_scheme` of an MRtrix image).
#[derive(Clone, Debug)]
pub struct FitFiles {
    /// The DWI series, NIfTI or MRtrix, 4D.
    pub dwi: PathBuf,
    /// The `.bval` file: one b-value (s/mm^2) per volume.
    pub bval: Option<PathBuf>,
    /// The `.bvec` file: three rows of one number per volume (FSL's layout), or one
    /// row of three per volume.
    pub bvec: Option<PathBuf>,
    /// Voxels to fit: nonzero values, the DWI's spatial shape; every voxel without one.
    pub mask: Option<PathBuf>,
}

/// The file that errors about the directions and the b-values name.
#[derive(Clone, Debug)]
pub struct GradientOrigin {
    /// The `.bvec` file, or the DWI when its `dw_scheme` gave the directions.
    pub directions: String,
    /// The `.bval` file, or the DWI when its `dw_scheme` gave the b-values.
    pub bvals: String,
}

/// The DWI series, its gradient table and the optional mask, mutually consistent: one
/// b-value and direction per volume, a mask of the DWI's spatial shape.
#[derive(Clone, Debug)]
pub struct FitInputs {
    /// The files they were read from.
    pub files: FitFiles,
    /// The DWI series with its header.
    pub dwi: Dwi,
    /// One b-value and unit direction per volume: a `.bvec`'s directions as stored (the
    /// caller applies its `--bvec-convention`), a `dw_scheme`'s turned into the voxel axes.
    pub gradients: GradientTable,
    /// Which files errors about the gradient table name.
    pub origin: GradientOrigin,
    /// Voxels to fit, [x, y, z]; None fits every voxel.
    pub mask: Option<Array3<bool>>,
}

impl FitInputs {
    /// Reads the DWI, the gradient table (the files, else the DWI's `dw_scheme`) and the
    /// mask, and checks them against each other; errors name the file and the field.
    pub fn load(files: FitFiles) -> Result<Self> {
        let name = files.dwi.display().to_string();
        // Only an MRtrix image may carry its table: a NIfTI DWI without the files is a
        // request to change, refused before the DWI is read.
        if files.bval.is_none() && files.bvec.is_none() && !is_mrtrix(&files.dwi) {
            return Err(Error::setting(
                DmriSetting::Bval,
                glyphcast::message![
                    format!("{name} is a NIfTI image, which carries no gradient table: give "),
                    DmriSetting::Bval,
                    " and ",
                    DmriSetting::Bvec,
                    " (an MRtrix .mif or .mih may carry its own, dw_scheme)"
                ],
            ));
        }
        let dwi = read_dwi(&files.dwi)?;
        let (gradients, origin) = match (&files.bval, &files.bvec) {
            (Some(bval), Some(bvec)) => (
                GradientTable::read(bval, bvec, dwi.volume_count(), &name)?,
                GradientOrigin {
                    directions: bvec.display().to_string(),
                    bvals: bval.display().to_string(),
                },
            ),
            (None, None) => {
                let Some(rows) = &dwi.dw_scheme else {
                    return Err(Error::input(
                        name,
                        "dw_scheme",
                        glyphcast::message![
                            "no gradient table in the file (an MRtrix image's dw_scheme): give ",
                            DmriSetting::Bval,
                            " and ",
                            DmriSetting::Bvec
                        ],
                    ));
                };
                let rotation = dwi.voxel_to_world()?.orthogonal_factor().ok_or_else(|| {
                    Error::input(
                        &name,
                        "transform",
                        "no rotation can be taken from the affine",
                    )
                })?;
                let table =
                    GradientTable::from_dw_scheme(rows, dwi.volume_count(), rotation, &name)?;
                (
                    table,
                    GradientOrigin {
                        directions: name.clone(),
                        bvals: name.clone(),
                    },
                )
            }
            _ => {
                return Err(Error::conflict(
                    DmriSetting::Bval,
                    glyphcast::error::Relation::Requires,
                    DmriSetting::Bvec,
                ));
            }
        };
        let mask = match &files.mask {
            Some(path) => Some(read_mask(
                path,
                dwi.spatial_shape(),
                &dwi.voxel_to_world()?,
                &name,
            )?),
            None => None,
        };
        Ok(Self {
            files,
            dwi,
            gradients,
            origin,
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
