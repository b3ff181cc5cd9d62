//! The stored order of DTI tensors (issue 26.1): each convention written by `fit` and read
//! back without an option; a `.mif` holds MRtrix's order (checked by an eigen
//! decomposition written here, independent of the library's permutations); an MRtrix
//! tensor `.mif` drawn as ellipsoids whose long axes, measured on the rendered surface,
//! lie along the eigenvectors; a misordered NIfTI refused; higher orders round-trip.
use crate::common;
use common::{axis_angle, fit_small_64d, fresh_dir, glyphcast, text};
use glam::{DMat3, DMat4, DQuat, DVec3, EulerRot};
use glyphcast::io::npy::read_npy_f32;
use glyphcast::scene::Scene;
use glyphcast_dmri::io::image::read_image;
use glyphcast_dmri::io::mif::{MifWrite, write_mif};
use glyphcast_dmri::io::nifti::{AffineSource, VoxelToWorld};
use glyphcast_dmri::volume::{Coefficients, Volume, VolumeRequest};
use nalgebra::{Matrix3, SymmetricEigen};
use ndarray::{Array4, ArrayD, IxDyn};
use std::path::{Path, PathBuf};

/// `glyphcast fit` of small_64D at `order` into `dir/NAME`, with `extra` flags.
fn fit(dir: &Path, name: &str, order: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["--order", order, "--quiet"];
    args.extend_from_slice(extra);
    let run = fit_small_64d(&args, &out);
    assert!(
        run.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    out
}

/// The tensors, the flags, and None where it draws, else the words of its error.
type RenderCase<'a> = (&'a Path, &'a [&'a str], Option<[&'a str; 2]>);

/// `glyphcast render --tensor FILE --order 2` with `extra` flags into `out`.
fn render_order2(tensors: &Path, extra: &[&str], out: &Path) -> std::process::Output {
    let mut args = vec!["render", "--tensor", text(tensors), "--order", "2"];
    args.extend_from_slice(extra);
    args.extend(["-o", text(out)]);
    glyphcast(&args)
}

/// The file's values as stored, [x, y, z, volume].
fn stored(path: &Path) -> Array4<f64> {
    let image = read_image(path).expect("image");
    image.data.into_dimensionality().expect("a 4D image")
}

/// The volume as `render --tensor FILE --order N` reads it, with no other option.
fn read_back(path: &Path, order: u32) -> Volume {
    let request = VolumeRequest {
        order: Some(order),
        ..Default::default()
    };
    request
        .read_volume(Coefficients::Tensor, path)
        .expect("read back without an option")
}

/// Eigenvalues, ascending, of the symmetric matrix with these entries.
fn eigenvalues(xx: f64, yy: f64, zz: f64, xy: f64, xz: f64, yz: f64) -> [f64; 3] {
    let m = Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
    let mut values: Vec<f64> = SymmetricEigen::new(m).eigenvalues.iter().copied().collect();
    values.sort_by(f64::total_cmp);
    [values[0], values[1], values[2]]
}

/// Each NIfTI convention is written in its order, records it, and reads back as the
/// glyphcast-order fit; the `.mif` holds MRtrix's order (its tensors have the NIfTI
/// tensors' eigenvalues when read as xx, yy, zz, xy, xz, yz, which a rotation to scanner
/// axes keeps).
#[test]
fn each_convention_is_written_and_read_back() {
    let dir = fresh_dir("tensor-order-conventions");
    let reference = fit(&dir, "glyphcast.nii", "2", &[]);
    let base = stored(&reference);
    let voxels = base.shape()[..3].iter().product::<usize>();
    // Each writer's order, spelled here: the index of each stored entry in glyphcast's
    // xx 0, xy 1, xz 2, yy 3, yz 4, zz 5.
    for (name, positions) in [
        ("fsl", [0, 1, 2, 3, 4, 5]),
        ("dipy", [0, 1, 3, 2, 4, 5]),
        ("mrtrix", [0, 3, 5, 1, 2, 4]),
    ] {
        let path = fit(
            &dir,
            &format!("{name}.nii.gz"),
            "2",
            &["--tensor-order", name],
        );
        let image = read_image(&path).expect("image");
        assert_eq!(
            image.description().as_deref(),
            Some(format!("glyphcast fit: symmetric tensor order 2 in {name} order").as_str())
        );
        let values = stored(&path);
        for (k, &p) in positions.iter().enumerate() {
            let (a, b) = (
                values.index_axis(ndarray::Axis(3), k),
                base.index_axis(ndarray::Axis(3), p),
            );
            assert_eq!(a, b, "{name}: stored entry {k}");
        }
        let volume = read_back(&path, 2);
        let glyphcast = read_back(&reference, 2);
        let mut compared = 0;
        for i in 0..10 {
            for j in 0..10 {
                for k in 0..10 {
                    let v = [i, j, k];
                    assert_eq!(volume.coefficients(v), glyphcast.coefficients(v), "{name}");
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, voxels);
    }
    // The .mif: MRtrix's order, in scanner axes.
    let mif = fit(&dir, "dt.mif", "2", &[]);
    let image = read_image(&mif).expect("mif");
    assert!(
        image
            .description()
            .is_some_and(|d| d.contains("in mrtrix order")),
        "{:?}",
        image.description()
    );
    let world = stored(&mif);
    let mut positive = 0;
    for ((i, j, k), _) in base.index_axis(ndarray::Axis(3), 0).indexed_iter() {
        let g = |c: usize| base[[i, j, k, c]];
        let m = |c: usize| world[[i, j, k, c]];
        let expected = eigenvalues(g(0), g(3), g(5), g(1), g(2), g(4));
        let got = eigenvalues(m(0), m(1), m(2), m(3), m(4), m(5));
        let scale = expected.iter().fold(1e-12f64, |m, v| m.max(v.abs()));
        for (a, b) in got.iter().zip(expected) {
            assert!(
                (a - b).abs() < 1e-5 * scale,
                "voxel {i},{j},{k}: {got:?} vs {expected:?}"
            );
        }
        // Diagonal entries first: positive wherever the tensor is positive definite.
        if expected[0] > 0.0 {
            assert!(m(0) > 0.0 && m(1) > 0.0 && m(2) > 0.0);
            positive += 1;
        }
    }
    assert!(positive > 500, "{positive} positive definite tensors");
    // Read back: in glyphcast's order, without an option, and not refused.
    let volume = read_back(&mif, 2);
    let v = [5, 5, 5];
    let c = volume.coefficients(v);
    let m = |k: usize| world[[5, 5, 5, k]];
    assert_eq!(c, vec![m(0), m(3), m(4), m(1), m(5), m(2)]);
    // A .mif cannot take another order.
    let out = fit_small_64d(
        &["--order", "2", "--tensor-order", "dipy"],
        &dir.join("no.mif"),
    );
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--tensor-order dipy"), "{stderr}");
    assert!(!dir.join("no.mif").exists());
}

/// An order-4 fit written to NIfTI and to `.mif` reads back without an option (the
/// `.mif` is not taken for `dwi2tensor -dkt`'s kurtosis tensor, since it records
/// glyphcast), in glyphcast's order as written; an order-4 `.mif` that records nothing is
/// refused until the order is named.
#[test]
fn higher_orders_read_back_what_glyphcast_writes() {
    let dir = fresh_dir("tensor-order-higher");
    let nifti = fit(&dir, "t4.nii.gz", "4", &[]);
    let mif = fit(&dir, "t4.mif", "4", &[]);
    for path in [&nifti, &mif] {
        let raw = stored(path);
        let volume = read_back(path, 4);
        let v = [4, 5, 6];
        let expected: Vec<f64> = (0..15).map(|k| raw[[4, 5, 6, k]]).collect();
        assert_eq!(volume.coefficients(v), expected, "{}", path.display());
    }
    let description = read_image(&nifti).unwrap().description().unwrap();
    assert_eq!(
        description,
        "glyphcast fit: symmetric tensor order 4 in glyphcast order"
    );
    // The same values in a .mif of no record.
    let raw: ArrayD<f64> = stored(&mif).into_dyn();
    let map = VoxelToWorld::new(DMat4::IDENTITY, AffineSource::Pixdim, "x", "transform").unwrap();
    let bare = dir.join("bare4.mif");
    write_mif(
        &bare,
        &MifWrite {
            data: &raw,
            voxel_to_world: &map,
            keys: &[],
        },
    )
    .unwrap();
    let request = VolumeRequest {
        order: Some(4),
        ..Default::default()
    };
    let err = request
        .read_volume(Coefficients::Tensor, &bare)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("dkt") && err.contains("tensor order glyphcast"),
        "{err}"
    );
    let named = VolumeRequest {
        tensor_order: Some("glyphcast".into()),
        ..request
    };
    assert!(named.read_volume(Coefficients::Tensor, &bare).is_ok());
}

/// Three prolate tensors along known directions (eigenvalues 1.7, 0.3, 0.3 e-3), as the
/// six entries (glyphcast order xx, xy, xz, yy, yz, zz) and the direction.
fn oriented_tensors() -> Vec<([f64; 6], DVec3)> {
    [(0.5, 0.3, 0.0), (-1.0, 0.6, 0.2), (2.2, -0.9, 0.7)]
        .into_iter()
        .map(|(a, b, c)| {
            let r = DMat3::from_quat(DQuat::from_euler(EulerRot::ZYX, a, b, c));
            let d = r * DMat3::from_diagonal(DVec3::new(1.7e-3, 0.3e-3, 0.3e-3)) * r.transpose();
            let entries = [
                d.x_axis.x, d.y_axis.x, d.z_axis.x, d.y_axis.y, d.z_axis.y, d.z_axis.z,
            ];
            (entries, r.x_axis)
        })
        .collect()
}

/// The tensors in a row of voxels along x, stored in MRtrix's order.
fn mrtrix_order_volume(tensors: &[([f64; 6], DVec3)]) -> ArrayD<f64> {
    let mut data = ArrayD::zeros(IxDyn(&[tensors.len(), 1, 1, 6]));
    for (i, (t, _)) in tensors.iter().enumerate() {
        let [xx, xy, xz, yy, yz, zz] = *t;
        for (k, value) in [xx, yy, zz, xy, xz, yz].into_iter().enumerate() {
            data[[i, 0, 0, k]] = value;
        }
    }
    data
}

/// An MRtrix-order tensor `.mif` drawn with `--glyph ellipsoid`: each ellipsoid's long
/// axis, the direction of its farthest surface point in the depth map, lies within a
/// degree of the tensor's principal eigenvector. The same values in a NIfTI (no record,
/// glyphcast's order assumed) are refused, naming MRtrix's order.
#[test]
fn mrtrix_tensor_mif_draws_ellipsoids_along_the_eigenvectors() {
    let dir = fresh_dir("tensor-order-mif-axes");
    let tensors = oriented_tensors();
    let data = mrtrix_order_volume(&tensors);
    let map = VoxelToWorld::new(DMat4::IDENTITY, AffineSource::Pixdim, "x", "transform").unwrap();
    let mif = dir.join("dt.mif");
    write_mif(
        &mif,
        &MifWrite {
            data: &data,
            voxel_to_world: &map,
            keys: &[("comments", "made by dwi2tensor".into())],
        },
    )
    .unwrap();
    let farthest = ellipsoid_axes(&dir, "e", &mif, &[]);
    assert_eq!(farthest.len(), 3);
    for (g, (axis, (_, e1))) in farthest.iter().zip(&tensors).enumerate() {
        let angle = axis_angle(*axis, *e1);
        eprintln!("glyph {g}: long axis {angle:.3} degrees from the eigenvector");
        assert!(angle < 1.0, "glyph {g}: {angle} degrees");
    }
    let nifti = dir.join("dt.nii");
    common::write_nifti(&nifti, &data, DMat4::IDENTITY);
    let recorded = fit(&dir, "dipy.nii", "2", &["--tensor-order", "dipy"]);
    let cases: [RenderCase; 3] = [
        // The MRtrix-order values in a NIfTI: glyphcast's order is assumed and the
        // values refute it.
        (
            &nifti,
            &["--glyph", "ellipsoid"],
            Some(["dt.nii", "--tensor-order mrtrix"]),
        ),
        // Named, it draws.
        (&nifti, &["--tensor-order", "mrtrix"], None),
        // An order given where the file records another is refused.
        (
            &recorded,
            &["--tensor-order", "mrtrix"],
            Some(["descrip", "DIPY"]),
        ),
    ];
    for (case, (tensors, flags, refusal)) in cases.into_iter().enumerate() {
        let image = dir.join(format!("case-{case}.png"));
        let out = render_order2(tensors, flags, &image);
        let stderr = String::from_utf8_lossy(&out.stderr);
        match refusal {
            Some(words) => {
                assert_eq!(out.status.code(), Some(1), "{flags:?}: {stderr}");
                assert!(
                    words.iter().all(|w| stderr.contains(w)),
                    "{flags:?}: {stderr}"
                );
                assert!(!image.exists(), "{flags:?}");
            }
            None => assert!(out.status.success(), "{flags:?}: {stderr}"),
        }
    }
}

/// `tensors` (order 2) drawn as ellipsoids at 720 x 240 with `extra` flags into `dir`
/// (files named `name`): each glyph's long axis ([`long_axes`]).
fn ellipsoid_axes(dir: &Path, name: &str, tensors: &Path, extra: &[&str]) -> Vec<DVec3> {
    let (png, npy, json) = (
        dir.join(format!("{name}.png")),
        dir.join(format!("{name}.npy")),
        dir.join(format!("{name}.json")),
    );
    let (w, h) = (720u32, 240u32);
    let (width, height) = (w.to_string(), h.to_string());
    let mut flags = vec![
        "--glyph",
        "ellipsoid",
        "--width",
        &width,
        "--height",
        &height,
    ];
    flags.extend(["--depth-out", text(&npy), "--save-scene", text(&json)]);
    flags.extend(extra);
    let out = render_order2(tensors, &flags, &png);
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    long_axes(&json, &npy, w, h)
}

/// Per glyph of the rendered scene `json` (saved with its depth map `npy`, w x h), the
/// direction from its centre to its farthest hit point: an ellipsoid's long axis.
fn long_axes(json: &Path, npy: &Path, w: u32, h: u32) -> Vec<DVec3> {
    let scene = Scene::load(json).expect("saved scene");
    let set = &scene.glyph_sets[0];
    let (_, depth) = read_npy_f32(npy).expect("depth");
    let mut farthest = vec![(0.0f64, DVec3::ZERO); set.centers.len()];
    for j in 0..h {
        for i in 0..w {
            let t = depth[(j * w + i) as usize];
            if t.is_nan() {
                continue;
            }
            let ray = scene.camera.ray(i, j, w, h);
            let p = ray.origin + ray.dir * t as f64;
            let (g, c) = set
                .centers
                .iter()
                .enumerate()
                .min_by(|a, b| a.1.distance(p).total_cmp(&b.1.distance(p)))
                .unwrap();
            let r = c.distance(p);
            if r > farthest[g].0 {
                farthest[g] = (r, p - *c);
            }
        }
    }
    farthest.into_iter().map(|(_, axis)| axis).collect()
}

/// FSL's `dtifit` fits in the frame of FSL's bvecs: the voxel axes with x negated on an
/// image whose affine has a positive determinant. The same stored values (three tensors
/// put in that frame) on an RAS image and on its LAS twin (whose FSL frame is its voxel
/// axes) draw ellipsoids along the tensors' world directions with `--tensor-order fsl`;
/// read as glyphcast's (plain voxel axes) the RAS ones turn. FSL's frame and scanner axes
/// (`--frame world`) are refused together.
#[test]
fn fsl_tensors_are_read_in_fsl_frame() {
    let dir = fresh_dir("tensor-order-fsl-frame");
    let tensors = oriented_tensors();
    let flip = DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0));
    let mut data = ArrayD::zeros(IxDyn(&[tensors.len(), 1, 1, 6]));
    for (i, (t, _)) in tensors.iter().enumerate() {
        let [xx, xy, xz, yy, yz, zz] = *t;
        let d = DMat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz]);
        let f = flip * d * flip;
        let entries = [
            f.x_axis.x, f.y_axis.x, f.z_axis.x, f.y_axis.y, f.z_axis.y, f.z_axis.z,
        ];
        for (k, value) in entries.into_iter().enumerate() {
            data[[i, 0, 0, k]] = value;
        }
    }
    let ras = dir.join("ras.nii");
    let las = dir.join("las.nii");
    common::write_nifti(&ras, &data, DMat4::IDENTITY);
    common::write_nifti(&las, &data, DMat4::from_mat3(flip));
    let axes = |name: &str, tensors_file: &Path, order: &str| {
        ellipsoid_axes(&dir, name, tensors_file, &["--tensor-order", order])
    };
    for (name, file) in [("ras", &ras), ("las", &las)] {
        for (g, (axis, (_, e1))) in axes(name, file, "fsl").iter().zip(&tensors).enumerate() {
            let angle = axis_angle(*axis, *e1);
            eprintln!("{name} glyph {g}: long axis {angle:.3} degrees from the eigenvector");
            assert!(angle < 1.0, "{name} glyph {g}: {angle} degrees");
        }
    }
    let turned = axes("voxel", &ras, "glyphcast")
        .iter()
        .zip(&tensors)
        .map(|(axis, (_, e1))| axis_angle(*axis, *e1))
        .fold(0.0f64, f64::max);
    assert!(
        turned > 10.0,
        "read as voxel axes: {turned} degrees at most"
    );
    let out = render_order2(
        &ras,
        &["--tensor-order", "fsl", "--frame", "world"],
        &dir.join("refused.png"),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("fsl") && stderr.contains("world"),
        "{stderr}"
    );
}

/// Volumes in memory (the Python module's path) are checked as NIfTI files are.
#[test]
fn a_misordered_array_is_refused() {
    let tensors = oriented_tensors();
    let dipy: Array4<f64> = Array4::from_shape_fn((3, 1, 1, 6), |(i, _, _, k)| {
        let [xx, xy, xz, yy, yz, zz] = tensors[i].0;
        [xx, xy, yy, xz, yz, zz][k]
    });
    let map = VoxelToWorld::new(DMat4::IDENTITY, AffineSource::Sform, "coeffs", "affine").unwrap();
    let request = VolumeRequest {
        order: Some(2),
        ..Default::default()
    };
    let err = request
        .memory_volume(Coefficients::Tensor, "coeffs", dipy.clone(), map)
        .unwrap_err();
    let text = err.to_string();
    assert!(
        text.starts_with("coeffs: values: 3 of 3 tensors are not positive definite"),
        "{text}"
    );
    assert!(text.contains("tensor order dipy"), "{text}");
    let named = VolumeRequest {
        tensor_order: Some("dipy".into()),
        ..request
    };
    let volume = named
        .memory_volume(Coefficients::Tensor, "coeffs", dipy, map)
        .expect("named");
    for (i, (t, _)) in tensors.iter().enumerate() {
        assert_eq!(volume.coefficients([i, 0, 0]), t.to_vec());
    }
}
