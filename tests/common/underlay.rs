//! Volume files for the underlay tests: order-2 tensors on one grid and a scalar image on
//! another (finer, shifted and turned), both placed in world space by their sforms.
use glam::{DMat4, DQuat, DVec3};
use glyphcast::demo::{direction, fibre_tensor};
use glyphcast::rng::SplitMix64;
use ndarray::{ArrayD, IxDyn};
use std::path::Path;

/// A 6 x 5 x 4 volume of order-2 tensors (prolate along a direction that turns with i)
/// with voxel size 2 mm and origin (-5, -4, -3).
pub fn tensor_volume(dir: &Path) -> (String, DMat4) {
    let dims = [6, 5, 4];
    let mut data = ArrayD::<f64>::zeros(IxDyn(&[dims[0], dims[1], dims[2], 6]));
    for i in 0..dims[0] {
        for j in 0..dims[1] {
            for k in 0..dims[2] {
                let d = direction(30.0 * i as f64, 10.0 * j as f64);
                let c = fibre_tensor(2, &[(d, 1.0)]);
                for (n, v) in c.iter().enumerate() {
                    data[[i, j, k, n]] = v + if n == 0 || n == 3 || n == 5 { 0.2 } else { 0.0 };
                }
            }
        }
    }
    let affine = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        DQuat::IDENTITY,
        DVec3::new(-5.0, -4.0, -3.0),
    );
    let path = dir.join("tensors.nii");
    super::write_nifti(&path, &data, affine);
    (path.display().to_string(), affine)
}

/// A scalar underlay on a finer (1.3 mm), shifted and slightly rotated grid covering the
/// tensor volume, with a smooth field plus noise.
pub fn scalar_underlay(dir: &Path, name: &str) -> String {
    let dims = [11, 10, 9];
    let mut rng = SplitMix64::new(3);
    let mut data = ArrayD::<f64>::zeros(IxDyn(&dims));
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let smooth = i as f64 * 7.0 + j as f64 * 3.0 - k as f64;
                data[[i, j, k]] = smooth + 20.0 * rng.unit();
            }
        }
    }
    let affine = DMat4::from_scale_rotation_translation(
        DVec3::splat(1.3),
        DQuat::from_rotation_z(0.1),
        DVec3::new(-6.5, -5.0, -5.0),
    );
    let path = dir.join(name);
    super::write_nifti(&path, &data, affine);
    path.display().to_string()
}

/// A new folder `dir` with the tensors of [`tensor_volume`] and the scalar underlay of
/// [`scalar_underlay`] ("fa.nii") in it: their paths.
pub fn tensors_with_underlay(dir: &Path) -> (String, String) {
    std::fs::create_dir_all(dir).expect("creating the underlay test folder");
    let (tensors, _) = tensor_volume(dir);
    (tensors, scalar_underlay(dir, "fa.nii"))
}
