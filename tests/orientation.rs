//! Which side of the image a glyph lands on, in every view and both conventions, judged
//! from the affine's RAS meaning (+x the subject's right, +y anterior, +z superior), not
//! from the voxel order: a volume with one glyph at a known anatomical corner, stored RAS
//! and LAS (x reversed, the same world grid), rendered by the real binary. And `--labels`
//! writes letters at the image's edges and nowhere else.
use crate::common;

use common::{flipped_in_x, glyphcast, text, write_nifti};
use glam::{DMat4, DVec3};
use glyphcast::io::npy::read_npy_f32;
use glyphcast::io::png::read_png_rgba8;
use ndarray::{ArrayD, IxDyn};
use std::path::{Path, PathBuf};

const SIDE: usize = 48;

/// A fresh folder for one test of this file.
fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("orientation/{name}"))
}

/// A 3 x 3 x 3 volume of order-2 tensors, zero but for a sphere at `voxel`, with 2 mm
/// voxels in RAS order centred on the origin.
fn one_glyph(voxel: [usize; 3]) -> (ArrayD<f64>, DMat4) {
    let mut data = ArrayD::zeros(IxDyn(&[3, 3, 3, 6]));
    for c in [0, 3, 5] {
        data[[voxel[0], voxel[1], voxel[2], c]] = 1.0;
    }
    let affine = DMat4::from_scale_rotation_translation(
        DVec3::splat(2.0),
        glam::DQuat::IDENTITY,
        DVec3::splat(-2.0),
    );
    (data, affine)
}

/// The voxel of `data` that holds the glyph.
fn glyph_voxel(data: &ArrayD<f64>) -> [usize; 3] {
    let (index, _) = data
        .indexed_iter()
        .find(|(_, v)| **v != 0.0)
        .expect("one glyph");
    [index[0], index[1], index[2]]
}

/// Renders `args` and returns the centroid of the glyph's pixels, as fractions of the
/// image from its left and from its top.
fn centroid(dir: &Path, name: &str, args: &[&str]) -> (f64, f64) {
    let (png, npy) = (
        dir.join(format!("{name}.png")),
        dir.join(format!("{name}.npy")),
    );
    let side = SIDE.to_string();
    let mut all = vec!["render"];
    all.extend(args);
    all.extend(["--width", &side, "--height", &side, "-o", text(&png)]);
    all.extend(["--depth-out", text(&npy)]);
    let out = glyphcast(&all);
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, depth) = read_npy_f32(&npy).expect("depth map");
    let hits: Vec<(f64, f64)> = depth
        .iter()
        .enumerate()
        .filter(|(_, d)| !d.is_nan())
        .map(|(n, _)| ((n % SIDE) as f64 + 0.5, (n / SIDE) as f64 + 0.5))
        .collect();
    assert!(
        hits.len() > 10,
        "{name}: the glyph covers {} pixels",
        hits.len()
    );
    let count = hits.len() as f64;
    let x = hits.iter().map(|h| h.0).sum::<f64>() / count;
    let y = hits.iter().map(|h| h.1).sum::<f64>() / count;
    (x / SIDE as f64, y / SIDE as f64)
}

/// Which way the glyph lies from the volume's centre, in world terms: +1 or -1 along
/// R, A and S (0 at the centre).
fn anatomical_side(voxel: [usize; 3], affine: DMat4) -> DVec3 {
    let position = affine.transform_point3(DVec3::from_array(voxel.map(|v| v as f64)));
    let centre = affine.transform_point3(DVec3::splat(1.0));
    (position - centre).signum()
        * (position - centre)
            .abs()
            .cmpgt(DVec3::splat(0.5))
            .into_f64()
}

trait IntoF64 {
    fn into_f64(self) -> DVec3;
}

impl IntoF64 for glam::BVec3 {
    fn into_f64(self) -> DVec3 {
        DVec3::new(
            f64::from(u8::from(self.x)),
            f64::from(u8::from(self.y)),
            f64::from(u8::from(self.z)),
        )
    }
}

/// Expected (horizontal, vertical) place of a glyph on side `s` (R, A, S signs) in view
/// `view`: -1 left / top, +1 right / bottom, 0 centre. Radiological puts the subject's
/// right on the image's left in axial and coronal views; sagittal views have anterior on
/// the left in both conventions; up is anterior (axial) or superior.
fn expected_place(view: &str, radiological: bool, s: DVec3) -> (f64, f64) {
    let right_on_right = if radiological { -1.0 } else { 1.0 };
    match view {
        "axial" => (right_on_right * s.x, -s.y),
        "coronal" => (right_on_right * s.x, -s.z),
        _ => (-s.y, -s.z),
    }
}

/// Asserts that `measured` (fractions of the image) lies on the `expected` side.
fn assert_side(name: &str, measured: (f64, f64), expected: (f64, f64)) {
    for (axis, m, e) in [
        ("horizontal", measured.0, expected.0),
        ("vertical", measured.1, expected.1),
    ] {
        let offset = m - 0.5;
        let ok = if e == 0.0 {
            offset.abs() < 0.05
        } else {
            offset * e > 0.15
        };
        assert!(ok, "{name}: {axis} place {m:.3}, expected side {e}");
    }
}

/// Renders the slice of each plane through the glyph at `voxel` of `path` (mapped by
/// `affine`, a permutation of axes with signs and sizes) in both conventions, and checks
/// where the glyph lands against its world side.
fn check_views(dir: &Path, storage: &str, path: &Path, voxel: [usize; 3], affine: DMat4) {
    let side = anatomical_side(voxel, affine);
    for (view, world_axis) in [("axial", 2), ("coronal", 1), ("sagittal", 0)] {
        // The voxel axis that runs along the plane's normal.
        let along = (0..3)
            .find(|&c| affine.col(c)[world_axis] != 0.0)
            .expect("a permutation");
        let slice = format!("{view}:{}", voxel[along]);
        for convention in ["radiological", "neurological"] {
            let name = format!("{storage}-{view}-{convention}");
            let args = [
                "--tensor",
                text(path),
                "--order",
                "2",
                "--slice",
                &slice,
                "--orientation",
                convention,
            ];
            let measured = centroid(dir, &name, &args);
            let expected = expected_place(view, convention == "radiological", side);
            assert_side(&name, measured, expected);
        }
    }
}

/// The glyph at the subject's right, anterior, superior corner, stored RAS and LAS: each
/// view in each convention shows it where the convention says, the same for both
/// storages.
#[test]
fn every_view_follows_the_convention_in_world_terms() {
    let dir = fresh_dir("views");
    let (ras, affine) = one_glyph([2, 2, 2]);
    let (las, las_affine) = flipped_in_x(&ras, affine);
    for (storage, data, affine) in [("ras", &ras, affine), ("las", &las, las_affine)] {
        let path = dir.join(format!("{storage}.nii.gz"));
        write_nifti(&path, data, affine);
        let voxel = glyph_voxel(data);
        let side = anatomical_side(voxel, affine);
        assert_eq!(
            side,
            DVec3::ONE,
            "{storage}: the glyph is right, anterior, superior"
        );
        check_views(&dir, storage, &path, voxel, affine);
    }
}

/// A volume stored sagittally (voxel i along world y, j along z, k along x): `--slice
/// axial` is still the world's axial plane (here constant j), and every view shows a
/// glyph at the subject's right, posterior, superior corner where the convention says.
#[test]
fn slice_names_are_world_planes_whatever_the_storage() {
    let dir = fresh_dir("sagittal-storage");
    let (ras, affine) = one_glyph([2, 0, 2]);
    let stored = ras.clone().permuted_axes(IxDyn(&[1, 2, 0, 3]));
    let stored_affine =
        DMat4::from_cols(affine.y_axis, affine.z_axis, affine.x_axis, affine.w_axis);
    let path = dir.join("sagittal.nii.gz");
    write_nifti(&path, &stored, stored_affine);
    let voxel = glyph_voxel(&stored);
    let side = anatomical_side(voxel, stored_affine);
    assert_eq!(
        side,
        DVec3::new(1.0, -1.0, 1.0),
        "right, posterior, superior"
    );
    check_views(&dir, "sagittal", &path, voxel, stored_affine);
}

/// Radiological is the default: no --orientation draws what --orientation radiological
/// draws, with the subject's right on the left of an axial view.
#[test]
fn radiological_is_the_default() {
    let dir = fresh_dir("default");
    let (data, affine) = one_glyph([2, 1, 1]);
    let path = dir.join("right.nii.gz");
    write_nifti(&path, &data, affine);
    let base = [
        "--tensor",
        text(&path),
        "--order",
        "2",
        "--slice",
        "axial:1",
    ];
    let default = centroid(&dir, "default", &base);
    assert!(
        default.0 < 0.35,
        "the subject's right on the left: {default:?}"
    );
    let mut explicit = base.to_vec();
    explicit.extend(["--orientation", "radiological"]);
    assert_eq!(default, centroid(&dir, "explicit", &explicit));
}

/// The three-slice view follows the convention too: a glyph on the subject's right (and
/// the middle of the other axes) is on the image's left radiologically, on its right
/// neurologically, for either storage.
#[test]
fn the_three_slice_view_follows_the_convention() {
    let dir = fresh_dir("three");
    let (ras, affine) = one_glyph([2, 1, 1]);
    let (las, las_affine) = flipped_in_x(&ras, affine);
    for (storage, data, affine) in [("ras", &ras, affine), ("las", &las, las_affine)] {
        let path = dir.join(format!("{storage}.nii.gz"));
        write_nifti(&path, data, affine);
        let [i, j, k] = glyph_voxel(data);
        let slices = format!("{i},{j},{k}");
        for (convention, right_side) in [("radiological", -1.0), ("neurological", 1.0)] {
            let name = format!("{storage}-{convention}");
            let args = [
                "--tensor",
                text(&path),
                "--order",
                "2",
                "--slices",
                &slices,
                "--orientation",
                convention,
            ];
            let (x, _) = centroid(&dir, &name, &args);
            assert!(
                (x - 0.5) * right_side > 0.1,
                "{name}: the subject's right at {x:.3} of the width"
            );
        }
    }
}

/// --labels draws letters only near the edges, at all four of them, never over the glyph
/// (letters: pixels no glyph covers, by the depth map, that are not the background), and
/// changes the letters when the convention changes (R on the left radiologically, L
/// neurologically).
#[test]
fn labels_are_drawn_at_the_four_edges_only() {
    let dir = fresh_dir("labels");
    let (data, affine) = one_glyph([2, 2, 1]);
    let path = dir.join("glyph.nii.gz");
    write_nifti(&path, &data, affine);
    let size = 160usize;
    let render = |name: &str, extra: &[&str]| -> Vec<(usize, usize)> {
        let png = dir.join(format!("{name}.png"));
        let npy = dir.join(format!("{name}.npy"));
        let side = size.to_string();
        let mut args = vec!["render", "--tensor", text(&path), "--order", "2"];
        args.extend(["--slice", "axial:1", "--width", &side, "--height", &side]);
        args.extend(["-o", text(&png), "--depth-out", text(&npy)]);
        args.extend(extra);
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (w, h, rgba) = read_png_rgba8(&png).expect("reading the PNG");
        assert_eq!((w as usize, h as usize), (size, size));
        let (_, depth) = read_npy_f32(&npy).expect("depth");
        let background = glyphcast::render::compose::montage::background_bytes(
            glyphcast::render::RenderSettings::default().background,
        );
        let glyphs = depth.iter().filter(|d| d.is_finite()).count();
        assert!(glyphs > 100, "{name}: {glyphs} glyph pixels");
        (0..size * size)
            .filter(|&n| depth[n].is_nan() && rgba[4 * n..4 * n + 4] != background[..])
            .map(|n| (n % size, n / size))
            .collect()
    };
    assert!(render("plain", &[]).is_empty(), "letters without --labels");
    let changed = render("labelled", &["--labels"]);
    // Letters are 5% of the side high (8 px here, at least 12), 0.3 of that from the edge.
    let band = size / 6;
    let near_edge =
        |&(x, y): &(usize, usize)| x < band || y < band || x >= size - band || y >= size - band;
    assert!(
        changed.iter().all(near_edge),
        "label pixels away from the edges"
    );
    let middle = |v: usize| v > size / 3 && v < 2 * size / 3;
    let edges = [
        changed
            .iter()
            .filter(|&&(x, y)| x < band && middle(y))
            .count(),
        changed
            .iter()
            .filter(|&&(x, y)| x >= size - band && middle(y))
            .count(),
        changed
            .iter()
            .filter(|&&(x, y)| y < band && middle(x))
            .count(),
        changed
            .iter()
            .filter(|&&(x, y)| y >= size - band && middle(x))
            .count(),
    ];
    assert!(
        edges.iter().all(|&n| n > 20),
        "pixels per edge (left, right, top, bottom): {edges:?}"
    );
    // Neurologically the left and right letters swap (R on the left becomes L), the top
    // one (A) stays: compare where the letters were drawn in each convention.
    let neurological_changed = render(
        "neurological",
        &["--labels", "--orientation", "neurological"],
    );
    let within = |pixels: &[(usize, usize)], keep: &dyn Fn(usize, usize) -> bool| {
        let mut kept: Vec<(usize, usize)> = pixels
            .iter()
            .copied()
            .filter(|&(x, y)| keep(x, y))
            .collect();
        kept.sort_unstable();
        kept
    };
    let left = |x: usize, y: usize| x < band && middle(y);
    let top = |x: usize, y: usize| y < band && middle(x);
    assert_ne!(
        within(&changed, &left),
        within(&neurological_changed, &left),
        "R becomes L"
    );
    assert_eq!(
        within(&changed, &top),
        within(&neurological_changed, &top),
        "A stays A"
    );
}

/// A scene file has no anatomy: --labels and --orientation are for volumes only.
#[test]
fn labels_and_orientation_need_a_volume() {
    let dir = fresh_dir("scene");
    let scene = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("tests/scenes");
    let first = std::fs::read_dir(&scene)
        .expect("scene folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .expect("a scene file");
    for flag in [&["--labels"][..], &["--orientation", "neurological"][..]] {
        let png = dir.join("x.png");
        let mut args = vec!["render", text(&first), "-o", text(&png)];
        args.extend(flag);
        let out = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains(flag[0]) && stderr.contains("volume input"),
            "{stderr}"
        );
        assert!(!png.exists());
    }
}
