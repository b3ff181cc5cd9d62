//! Voxel to world coordinates of a NIfTI-1 or NIfTI-2 file, chosen the way the standard's
//! `nifti1.h` describes: the sform when `sform_code` > 0 (method 3), else the qform when
//! `qform_code` > 0 (method 2: quaternion b, c, d with a = sqrt(1 - b^2 - c^2 - d^2),
//! voxel sizes `pixdim[1..3]` and qfac = the sign of `pixdim[0]`, which flips the third
//! axis), else plain scaling by pixdim (method 1, no offset). Voxel (i, j, k) lands at
//! affine * (i, j, k, 1).
//! A NIfTI-1 header's float32 fields are widened to f64 exactly, so both versions go
//! through the same code.
use super::header::NiftiHeader;
use glam::{DMat3, DMat4, DVec3, DVec4};
use nalgebra::Matrix3;

use glyphcast::{Error, Result};

/// How far above 1 the float32 b^2 + c^2 + d^2 may be before the quaternion is refused.
const QUATERNION_SLACK: f64 = 1e-4;

/// Which header fields the affine came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AffineSource {
    /// `sform_code` > 0: the `srow_x/y/z` rows (method 3).
    Sform,
    /// `qform_code` > 0 and `sform_code` 0: the quaternion, voxel sizes and offsets (method 2).
    Qform,
    /// Neither code set: pixdim scaling only.
    Pixdim,
    /// An MRtrix header's `transform` and `vox` (see `io::mif`).
    MrtrixTransform,
}

/// A volume's voxel-to-world map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelToWorld {
    /// Maps voxel indices (i, j, k, 1) to world coordinates, in the file's units (usually mm).
    pub affine: DMat4,
    /// Which header fields `affine` came from.
    pub source: AffineSource,
}

impl VoxelToWorld {
    /// The affine of `header` (sform, else qform, else pixdim); `file` names errors.
    /// Err when the chosen fields are not finite, a voxel size is not positive, or the
    /// linear part is singular.
    pub fn from_header(header: &NiftiHeader, file: &str) -> Result<Self> {
        let (affine, source, field) = if header.sform_code > 0 {
            (sform_affine(header), AffineSource::Sform, "srow_x/y/z")
        } else if header.qform_code > 0 {
            (
                qform_affine(header, file)?,
                AffineSource::Qform,
                "quatern_b/c/d",
            )
        } else {
            (pixdim_affine(header, file)?, AffineSource::Pixdim, "pixdim")
        };
        Self::new(affine, source, file, field)
    }

    /// Checks `affine`: Err naming `file` and `field` when it is not finite or its linear
    /// part is singular.
    pub fn new(affine: DMat4, source: AffineSource, file: &str, field: &str) -> Result<Self> {
        if !affine.is_finite() {
            return Err(Error::input(file, field, "the affine is not finite"));
        }
        let linear = DMat3::from_mat4(affine);
        let scale = voxel_sizes(linear).max_element();
        if linear.determinant().abs() <= 1e-12 * scale.powi(3) {
            return Err(Error::input(
                file,
                field,
                format!("the affine is singular: {}", show_rows(affine)),
            ));
        }
        Ok(Self { affine, source })
    }

    /// World position of voxel (i, j, k) (fractional indices allowed).
    pub fn voxel_center(&self, index: DVec3) -> DVec3 {
        self.affine.transform_point3(index)
    }

    /// The 3x3 linear part A: column c is the world step of one voxel along axis c.
    pub fn linear(&self) -> DMat3 {
        DMat3::from_mat4(self.affine)
    }

    /// World length of one voxel step along each voxel axis.
    pub fn voxel_sizes(&self) -> DVec3 {
        voxel_sizes(self.linear())
    }

    /// The orthogonal polar factor R = U V^T of A = U S V^T: the rotation (or, with det -1,
    /// rotation and reflection) closest to A. None if the SVD does not converge.
    pub fn orthogonal_factor(&self) -> Option<DMat3> {
        let a = self.linear();
        let cols = a.to_cols_array();
        let matrix = Matrix3::from_column_slice(&cols);
        let svd = matrix.try_svd(true, true, f64::EPSILON, 1000)?;
        let r = svd.u? * svd.v_t?;
        Some(DMat3::from_cols_slice(r.as_slice()))
    }
}

fn voxel_sizes(linear: DMat3) -> DVec3 {
    DVec3::new(
        linear.x_axis.length(),
        linear.y_axis.length(),
        linear.z_axis.length(),
    )
}

fn show_rows(affine: DMat4) -> String {
    let rows: Vec<String> = (0..3)
        .map(|r| {
            let row = affine.row(r);
            format!("[{} {} {} {}]", row.x, row.y, row.z, row.w)
        })
        .collect();
    rows.join(" ")
}

/// Method 3: the rows srow_x, srow_y, srow_z.
fn sform_affine(header: &NiftiHeader) -> DMat4 {
    DMat4::from_cols(
        DVec4::from_array(header.srow_x),
        DVec4::from_array(header.srow_y),
        DVec4::from_array(header.srow_z),
        DVec4::W,
    )
    .transpose()
}

/// Method 2: R(quaternion) * diag(dx, dy, qfac dz) + (qoffset_x, qoffset_y, qoffset_z).
fn qform_affine(header: &NiftiHeader, file: &str) -> Result<DMat4> {
    let (mut b, mut c, mut d) = (header.quatern_b, header.quatern_c, header.quatern_d);
    let sum = b * b + c * c + d * d;
    if !sum.is_finite() || sum > 1.0 + QUATERNION_SLACK {
        return Err(Error::input(
            file,
            "quatern_b/c/d",
            format!("b^2 + c^2 + d^2 = {sum} is above 1: not part of a unit quaternion"),
        ));
    }
    // nifti1.h: a = sqrt(1 - b^2 - c^2 - d^2); where that is about 0, (b, c, d) is
    // renormalised and a = 0 (a 180 degree rotation stored in float32).
    let a = if 1.0 - sum < 1e-7 {
        let norm = sum.sqrt();
        (b, c, d) = (b / norm, c / norm, d / norm);
        0.0
    } else {
        (1.0 - sum).sqrt()
    };
    let rotation = DMat3::from_cols(
        DVec3::new(
            a * a + b * b - c * c - d * d,
            2.0 * (b * c + a * d),
            2.0 * (b * d - a * c),
        ),
        DVec3::new(
            2.0 * (b * c - a * d),
            a * a + c * c - b * b - d * d,
            2.0 * (c * d + a * b),
        ),
        DVec3::new(
            2.0 * (b * d + a * c),
            2.0 * (c * d - a * b),
            a * a + d * d - b * b - c * c,
        ),
    );
    let qfac = if header.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
    let sizes = pixdim_sizes(header, file)? * DVec3::new(1.0, 1.0, qfac);
    let linear = rotation * DMat3::from_diagonal(sizes);
    let offset = DVec3::new(header.quatern_x, header.quatern_y, header.quatern_z);
    Ok(DMat4::from_cols(
        linear.x_axis.extend(0.0),
        linear.y_axis.extend(0.0),
        linear.z_axis.extend(0.0),
        offset.extend(1.0),
    ))
}

/// Method 1: diag(pixdim[1], pixdim[2], pixdim[3]), no offset.
fn pixdim_affine(header: &NiftiHeader, file: &str) -> Result<DMat4> {
    Ok(DMat4::from_scale(pixdim_sizes(header, file)?))
}

fn pixdim_sizes(header: &NiftiHeader, file: &str) -> Result<DVec3> {
    let mut sizes = [0.0; 3];
    for (axis, size) in sizes.iter_mut().enumerate() {
        let value = header.pixdim[axis + 1];
        if !(value.is_finite() && value > 0.0) {
            return Err(Error::input(
                file,
                format!("pixdim[{}]", axis + 1),
                format!("voxel size must be positive and finite, got {value}"),
            ));
        }
        *size = value;
    }
    Ok(DVec3::from_array(sizes))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> NiftiHeader {
        NiftiHeader {
            sform_code: 0,
            qform_code: 0,
            pixdim: [1.0, 2.0, 3.0, 4.0, 1.0, 1.0, 1.0, 1.0],
            ..NiftiHeader::default()
        }
    }

    #[test]
    fn pixdim_scaling_when_no_code_is_set() {
        let map = VoxelToWorld::from_header(&header(), "h.nii").unwrap();
        assert_eq!(map.source, AffineSource::Pixdim);
        let p = map.voxel_center(DVec3::new(1.0, 1.0, 1.0));
        assert_eq!(p, DVec3::new(2.0, 3.0, 4.0));
    }

    #[test]
    fn qform_rotates_90_degrees_about_z() {
        let half = std::f64::consts::FRAC_1_SQRT_2;
        let h = NiftiHeader {
            qform_code: 1,
            quatern_d: half,
            quatern_x: 5.0,
            ..header()
        };
        let map = VoxelToWorld::from_header(&h, "h.nii").unwrap();
        assert_eq!(map.source, AffineSource::Qform);
        let p = map.voxel_center(DVec3::new(1.0, 0.0, 0.0));
        assert!((p - DVec3::new(5.0, 2.0, 0.0)).length() < 1e-6, "{p}");
        let r = map.orthogonal_factor().unwrap();
        assert!((r * DVec3::X - DVec3::Y).length() < 1e-6);
    }

    #[test]
    fn bad_fields_are_named() {
        let h = NiftiHeader {
            pixdim: [1.0, 2.0, 0.0, 4.0, 1.0, 1.0, 1.0, 1.0],
            ..header()
        };
        let err = VoxelToWorld::from_header(&h, "h.nii")
            .unwrap_err()
            .to_string();
        assert!(err.contains("h.nii") && err.contains("pixdim[2]"), "{err}");
        let h = NiftiHeader {
            qform_code: 1,
            quatern_b: 0.9,
            quatern_c: 0.9,
            ..header()
        };
        let err = VoxelToWorld::from_header(&h, "h.nii")
            .unwrap_err()
            .to_string();
        assert!(err.contains("quatern_b/c/d"), "{err}");
        let h = NiftiHeader {
            sform_code: 1,
            srow_z: [0.0; 4],
            ..header()
        };
        let err = VoxelToWorld::from_header(&h, "h.nii")
            .unwrap_err()
            .to_string();
        assert!(err.contains("singular"), "{err}");
    }
}
