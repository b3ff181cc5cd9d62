//! Synthetic NIfTI files with the test affine: a 90 degree rotation about z, voxel sizes
//! 2, 3, 4 and an offset, stored as sform, as qform, or as qform with qfac -1.
use glam::{DMat3, DMat4, DVec3};
use glyphcast::demo::fibre_tensor;
use ndarray::{Array3, Array4, ArrayD};
use nifti::NiftiHeader;
use nifti::writer::WriterOptions;
use std::path::{Path, PathBuf};

/// How the test affine is stored in the header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    Sform,
    Qform,
    /// Qform with pixdim[0] = -1: the third voxel axis is flipped.
    QformFlipped,
    /// An sform turned by 35 degrees about (1, 2, 2) instead of 90 about z: unlike a
    /// quarter turn, R and R^T differ even for even glyphs.
    Oblique,
}

pub const ALL_STORAGES: [Storage; 4] = [
    Storage::Sform,
    Storage::Qform,
    Storage::QformFlipped,
    Storage::Oblique,
];

fn oblique_rotation() -> DMat3 {
    DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 2.0) / 3.0, 35f64.to_radians())
}

pub const OFFSET: DVec3 = DVec3::new(10.0, -20.0, 30.0);

/// The affine the header describes, written out by hand: voxel axis i goes to world +y
/// (2 mm), j to world -x (3 mm), k to world +z (4 mm), or -z when flipped.
pub fn expected_affine(storage: Storage) -> DMat4 {
    if storage == Storage::Oblique {
        let linear = oblique_rotation() * DMat3::from_diagonal(DVec3::new(2.0, 3.0, 4.0));
        return DMat4::from_cols(
            linear.x_axis.extend(0.0),
            linear.y_axis.extend(0.0),
            linear.z_axis.extend(0.0),
            OFFSET.extend(1.0),
        );
    }
    let k = if storage == Storage::QformFlipped {
        -4.0
    } else {
        4.0
    };
    DMat4::from_cols(
        glam::DVec4::new(0.0, 2.0, 0.0, 0.0),
        glam::DVec4::new(-3.0, 0.0, 0.0, 0.0),
        glam::DVec4::new(0.0, 0.0, k, 0.0),
        OFFSET.extend(1.0),
    )
}

/// The orthogonal part of the expected affine: where each voxel axis points in the world.
pub fn expected_rotation(storage: Storage) -> DMat3 {
    if storage == Storage::Oblique {
        return oblique_rotation();
    }
    let k = if storage == Storage::QformFlipped {
        -1.0
    } else {
        1.0
    };
    DMat3::from_cols(DVec3::Y, DVec3::NEG_X, DVec3::new(0.0, 0.0, k))
}

pub fn header(storage: Storage) -> NiftiHeader {
    let mut h = NiftiHeader {
        pixdim: [1.0, 2.0, 3.0, 4.0, 1.0, 1.0, 1.0, 1.0],
        sform_code: 0,
        qform_code: 0,
        ..NiftiHeader::default()
    };
    match storage {
        Storage::Sform => {
            h.sform_code = 2;
            h.srow_x = [0.0, -3.0, 0.0, 10.0];
            h.srow_y = [2.0, 0.0, 0.0, -20.0];
            h.srow_z = [0.0, 0.0, 4.0, 30.0];
            // A qform that disagrees, to show that the sform wins.
            h.qform_code = 1;
        }
        Storage::Oblique => {
            h.sform_code = 1;
            let affine = expected_affine(storage);
            let row = |r: usize| affine.row(r).to_array().map(|v| v as f32);
            (h.srow_x, h.srow_y, h.srow_z) = (row(0), row(1), row(2));
        }
        Storage::Qform | Storage::QformFlipped => {
            h.qform_code = 1;
            // 90 degrees about z: (a, b, c, d) = (cos 45, 0, 0, sin 45).
            h.quatern_d = std::f32::consts::FRAC_1_SQRT_2;
            (h.quatern_x, h.quatern_y, h.quatern_z) = (10.0, -20.0, 30.0);
            if storage == Storage::QformFlipped {
                h.pixdim[0] = -1.0;
            }
        }
    }
    h
}

pub fn scratch(name: &str) -> PathBuf {
    let dir = crate::common::output_dir().join("volume").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creating a test folder");
    dir
}

/// Writes `data` (any rank) as float32 with `header`'s geometry.
pub fn write(path: &Path, header: &NiftiHeader, data: &ArrayD<f64>) {
    let data = data.mapv(|v| v as f32);
    WriterOptions::new(path)
        .reference_header(header)
        .write_nifti(&data)
        .expect("writing a test NIfTI");
}

pub fn write4(path: &Path, storage: Storage, data: &Array4<f64>) {
    write(path, &header(storage), &data.clone().into_dyn());
}

pub fn write_mask(path: &Path, storage: Storage, data: &Array3<f64>) {
    write(path, &header(storage), &data.clone().into_dyn());
}

/// A volume of `dims` whose voxel (i, j, k) holds `glyph(i, j, k)`.
pub fn volume(
    dims: [usize; 3],
    count: usize,
    glyph: impl Fn([usize; 3]) -> Vec<f64>,
) -> Array4<f64> {
    Array4::from_shape_fn((dims[0], dims[1], dims[2], count), |(i, j, k, c)| {
        glyph([i, j, k])[c]
    })
}

/// An isotropic order-2 tensor c I whose c identifies the voxel: 1 + i + 10 j + 100 k.
pub fn labelled_sphere(voxel: [usize; 3]) -> Vec<f64> {
    let c = voxel_label(voxel);
    vec![c, 0.0, 0.0, c, 0.0, c]
}

pub fn voxel_label([i, j, k]: [usize; 3]) -> f64 {
    1.0 + i as f64 + 10.0 * j as f64 + 100.0 * k as f64
}

/// The voxel of a label (labels of voxels with i, j < 10).
pub fn label_voxel(label: f64) -> [usize; 3] {
    let n = (label - 1.0).round() as usize;
    [n % 10, (n / 10) % 10, n / 100]
}

/// An order-2 tensor with one long lobe along `axis`: 1 along it, 0.1 across.
pub fn lobe_tensor(axis: DVec3) -> Vec<f64> {
    let mut t = fibre_tensor(2, &[(axis, 0.9)]);
    for (slot, add) in [(0, 0.1), (3, 0.1), (5, 0.1)] {
        t[slot] += add;
    }
    t
}
