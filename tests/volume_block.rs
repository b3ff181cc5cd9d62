//! `render --block`: every voxel of `--voxels` as glyphs in 3D, on the fODFs and tensors
//! glyphcast fits to DIPY's small_64D (tests/data/dipy). The voxels expected, the mask's
//! count and the box's corners are worked out here from the files, not by the library's
//! selection; the GPU's depth map is compared with the float64 reference of the scene it
//! saved. Combinations a block does not take are refused before anything is written.
use crate::common::{fit_dti_small_64d, fit_small_64d, fresh_dir, glyphcast, text, write_nifti};
use glam::{DMat4, DVec3};
use glyphcast::accuracy::compare_depth;
use glyphcast::camera::Projection;
use glyphcast::glyph::reference::reference_depth;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::scene::Scene;
use glyphcast_dmri::io::nifti::{VoxelToWorld, read_nifti};
use std::path::{Path, PathBuf};

/// The voxel-to-world map of a NIfTI file, read from its header.
fn affine_of(path: &Path) -> VoxelToWorld {
    read_nifti(path).expect("reading the NIfTI").voxel_to_world
}

/// The 4x4 affine of `map`, for writing an image on the same grid.
fn matrix_of(map: &VoxelToWorld) -> DMat4 {
    DMat4::from_mat3_translation(map.linear(), map.voxel_center(DVec3::ZERO))
}

/// Whether the test mask keeps voxel (i, j, k): four voxels of every five.
fn kept(voxel: [usize; 3]) -> bool {
    !(voxel[0] + 2 * voxel[1] + 3 * voxel[2]).is_multiple_of(5)
}

/// A 10 x 10 x 10 mask on `map`'s grid that keeps what [`kept`] keeps.
fn write_mask(path: &Path, map: &VoxelToWorld) {
    let mask = ndarray::ArrayD::from_shape_fn(vec![10, 10, 10], |index| {
        f64::from(u8::from(kept([index[0], index[1], index[2]])))
    });
    write_nifti(path, &mask, matrix_of(map));
}

/// The outputs of one render: the PNG, the depth map and the saved scene.
struct Outputs {
    png: PathBuf,
    depth: PathBuf,
    scene: PathBuf,
}

impl Outputs {
    fn in_dir(dir: &Path, name: &str) -> Self {
        Outputs {
            png: dir.join(format!("{name}.png")),
            depth: dir.join(format!("{name}.npy")),
            scene: dir.join(format!("{name}.json")),
        }
    }

    fn args(&self) -> [&str; 6] {
        [
            "-o",
            text(&self.png),
            "--depth-out",
            text(&self.depth),
            "--save-scene",
            text(&self.scene),
        ]
    }
}

/// A block of the real fODFs (band 8) and one of the real tensors (order 2), each with
/// the mask: the report counts every voxel of the range, the saved scene holds one glyph
/// at the centre of each voxel the mask keeps and no other, the perspective camera looks
/// from anterior-superior-left and has the box's corners in view, and the depth map
/// agrees with the float64 reference in coverage and depth; the validation layer is on.
#[test]
fn a_block_of_a_real_volume_draws_every_voxel_of_its_range() {
    let dir = fresh_dir("block-real");
    let fod = dir.join("fod.nii.gz");
    let run = fit_small_64d(&["--odf", "csd", "--order", "8", "--quiet"], &fod);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let dti = fit_dti_small_64d(&dir);
    let map = affine_of(&fod);
    let mask = dir.join("mask.nii.gz");
    write_mask(&mask, &map);
    let (width, height) = (320u32, 256u32);
    // Each case: its name, the volume, the input flags and the block.
    type Case<'a> = (
        &'a str,
        &'a Path,
        &'a [&'a str],
        [std::ops::Range<usize>; 3],
    );
    let cases: [Case; 2] = [
        (
            "fod",
            &fod,
            &["--sh", text(&fod), "--norm", "per-glyph"],
            [2..8, 1..9, 3..7],
        ),
        (
            "dti",
            &dti,
            &["--tensor", text(&dti), "--order", "2"],
            [0..10, 4..7, 5..10],
        ),
    ];
    for (name, file, input, block) in cases {
        let outputs = Outputs::in_dir(&dir, name);
        let voxels = block
            .iter()
            .map(|r| format!("{}:{}", r.start, r.end))
            .collect::<Vec<_>>()
            .join(",");
        let mut args = vec!["render", "--block", "--voxels", &voxels, "--mask"];
        args.push(text(&mask));
        args.extend(input);
        let (w, h) = (width.to_string(), height.to_string());
        args.extend(["--width", &w, "--height", &h]);
        args.extend(outputs.args());
        let run = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{name}: {stderr}");

        // Every voxel of the range, counted here.
        let mut expected = Vec::new();
        let mut masked_out = 0;
        for k in block[2].clone() {
            for j in block[1].clone() {
                for i in block[0].clone() {
                    if kept([i, j, k]) {
                        expected.push(map.voxel_center(DVec3::new(i as f64, j as f64, k as f64)));
                    } else {
                        masked_out += 1;
                    }
                }
            }
        }
        let selected = block.iter().map(|r| r.len()).product::<usize>();
        let line = format!(
            "volume: {}: block {voxels}: {} glyphs from {selected} voxels ({masked_out} \
             masked out, 0 not finite, 0 zero, 0 below --min-amplitude)",
            file.display(),
            expected.len()
        );
        assert!(stderr.contains(&line), "{name}: no '{line}' in:\n{stderr}");

        let saved = Scene::load(&outputs.scene).expect("the saved scene");
        assert_eq!(
            saved.glyph_sets.len(),
            1,
            "{name}: a block is one glyph set"
        );
        let centers = &saved.glyph_sets[0].centers;
        assert_eq!(centers.len(), expected.len(), "{name}");
        for (n, center) in expected.iter().enumerate() {
            let matches = centers
                .iter()
                .filter(|c| (**c - *center).length() < 1e-6)
                .count();
            assert_eq!(matches, 1, "{name}: voxel {n} of the range, at {center}");
        }

        // Perspective, from anterior-superior-left (radiological), the box in view.
        let camera = &saved.camera;
        assert!(matches!(camera.projection, Projection::Perspective { .. }));
        let from = (camera.eye - camera.target).normalize();
        let corner_direction = DVec3::new(-1.0, 1.0, 1.0).normalize();
        assert!((from - corner_direction).length() < 1e-9, "{name}: {from}");
        let (sw, sh) = (saved.image.width, saved.image.height);
        assert_eq!((sw, sh), (width, height));
        let clip = camera.view_projection(sw, sh, 1e-3, 1e3);
        for corner in 0..8 {
            let voxel = DVec3::from_array(std::array::from_fn(|axis| {
                let range = &block[axis];
                let end = if corner & (1 << axis) == 0 {
                    range.start
                } else {
                    range.end
                };
                end as f64 - 0.5
            }));
            let ndc = clip.project_point3(map.voxel_center(voxel));
            assert!(
                ndc.x.abs() <= 1.0 + 1e-9 && ndc.y.abs() <= 1.0 + 1e-9,
                "{name}: corner {corner} out of view: {ndc}"
            );
        }

        // The depth map is the float64 reference's, in coverage and depth: every pixel
        // outside the silhouette band within 1e-3 of the largest glyph's radius, the
        // glyphs behind others included.
        let (shape, rendered) = glyphcast::io::npy::read_npy_f32(&outputs.depth).expect("depth");
        assert_eq!(shape, vec![height as usize, width as usize]);
        let sets = prepare_scene(&saved, 0.0).expect("preparing");
        let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
        assert_eq!(world.len(), expected.len());
        let reference = reference_depth(&world, camera, sw, sh);
        let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
        let c = compare_depth(&rendered, &reference, sw as usize, sh as usize, scale);
        eprintln!("{name}: {c}");
        assert!(
            c.covered > (sw * sh / 20) as usize,
            "{name}: the block fills the view: {c}"
        );
        assert!(
            c.holes == 0 && c.false_hits == 0 && c.median_error < 1e-3 && c.max_error < 1e-3,
            "{name}: {c}"
        );
    }
}

/// What a block does not go with: a slice, three slices, a montage and an underlay (a
/// usage error naming both flags), ranges outside the volume (naming the file and
/// --voxels), and a block of more than 100000 glyphs (naming --voxels and --mask). No
/// output is written, not even the scene file.
#[test]
fn what_a_block_does_not_take_is_refused_and_nothing_is_written() {
    let dir = fresh_dir("block-refusals");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).expect("output folder");
    let coef = crate::common::dipy_data("func_coef.nii.gz");
    let sh = [
        "--sh",
        text(&coef),
        "--basis",
        "tournier07",
        "--legacy",
        "--block",
    ];
    let outputs = Outputs::in_dir(&out, "refused");
    // A montage refuses --save-scene on its own, first: those runs write no scene.
    let run = |extra: &[&str]| {
        let mut args = vec!["render"];
        args.extend(sh);
        args.extend(extra);
        let montage = extra.iter().any(|a| matches!(*a, "--views" | "--lightbox"));
        let take = if montage { 4 } else { 6 };
        args.extend(&outputs.args()[..take]);
        glyphcast(&args)
    };
    let check = |extra: &[&str], code: i32, words: &[&str]| {
        let result = run(extra);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(code), "{extra:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{extra:?}: {stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{extra:?}: {stderr}");
        for word in words {
            assert!(
                errors[0].contains(word),
                "{extra:?}: no '{word}' in {}",
                errors[0]
            );
        }
        let left: Vec<_> = std::fs::read_dir(&out).expect("listing").collect();
        assert!(left.is_empty(), "{extra:?}: output left behind: {left:?}");
    };
    for (extra, flag) in [
        (&["--slice", "axial"][..], "--slice,"),
        (&["--slices", "mid"][..], "--slices,"),
        (&["--views", "axial,coronal"][..], "--views,"),
        (&["--lightbox", "4"][..], "--lightbox,"),
    ] {
        check(extra, 2, &["give either --block or", flag, "not both"]);
    }
    check(
        &["--underlay", text(&coef)],
        2,
        &["--block does not go with --underlay"],
    );
    // func_coef is 2 x 3 x 4 voxels.
    check(
        &["--voxels", "0:2,0:3,4:6"],
        1,
        &[
            "func_coef.nii.gz",
            "voxels",
            "leave no voxel of this 2x3x4 volume",
        ],
    );

    // 47 x 47 x 46 = 101614 voxels of finite tensors: more than a block draws.
    let big = dir.join("big.nii.gz");
    let tensors = ndarray::ArrayD::from_shape_fn(vec![47, 47, 46, 6], |index| {
        if matches!(index[3], 0 | 3 | 5) {
            1.0
        } else {
            0.0
        }
    });
    write_nifti(&big, &tensors, DMat4::IDENTITY);
    let mut args = vec!["render", "--tensor", text(&big), "--order", "2", "--block"];
    args.extend(outputs.args());
    let result = glyphcast(&args);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    for word in [
        "big.nii.gz: block: the block 0:47,0:47,0:46 holds 101614 voxels",
        "more than the 100000 glyphs a block draws",
        "--voxels",
        "--mask",
    ] {
        assert!(stderr.contains(word), "no '{word}' in {stderr}");
    }
    let left: Vec<_> = std::fs::read_dir(&out).expect("listing").collect();
    assert!(left.is_empty(), "output left behind: {left:?}");
}

/// `view --block` in a real window: the block orbits (the camera turns about its centre at
/// the same distance), a slice move is declined with a note, the validation layer stays
/// quiet, and the screenshot is what `render` draws of the scene the viewer saved.
#[test]
fn the_viewer_orbits_a_block() {
    use crate::common::window::{Xvfb, assert_clean, differing_pixels, out, path_str, render};
    let Some(x) = Xvfb::start("the_viewer_orbits_a_block") else {
        return;
    };
    let coef = crate::common::dipy_data("func_coef.nii.gz");
    let sh = [
        "--sh",
        text(&coef),
        "--basis",
        "tournier07",
        "--legacy",
        "--block",
    ];
    let size = ["--width", "160", "--height", "120"];
    let (shot, seen, home) = (
        out("block-shot.png"),
        out("block-seen.json"),
        out("block-home.json"),
    );
    let mut args: Vec<&str> = sh.to_vec();
    args.extend(size);
    args.extend([
        "--frames",
        "6",
        "--script",
        "slice:+1,orbit:40:15,wait",
        "--screenshot",
        path_str(&shot),
        "--save-scene",
        path_str(&seen),
    ]);
    let output = x.view(&args);
    assert_clean(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("a block has no slice to move"), "{stderr}");

    // The block as `render --block` frames it: the viewer's home camera.
    let mut args = vec!["render"];
    args.extend(sh);
    args.extend(size);
    let home_png = out("block-home.png");
    args.extend(["-o", path_str(&home_png), "--save-scene", path_str(&home)]);
    let run = glyphcast(&args);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let (seen_scene, home_scene) = (
        Scene::load(&seen).expect("the viewer's scene"),
        Scene::load(&home).expect("the rendered scene"),
    );
    // Every voxel of the 2 x 3 x 4 volume, one glyph set, as render draws it.
    assert_eq!(seen_scene.glyph_sets, home_scene.glyph_sets);
    assert_eq!(seen_scene.glyph_sets.len(), 1);
    assert_eq!(seen_scene.glyph_sets[0].len(), 24);
    let (a, b) = (&seen_scene.camera, &home_scene.camera);
    assert!(
        (a.target - b.target).length() < 1e-9,
        "the orbit keeps the target"
    );
    let (da, db) = ((a.eye - a.target).length(), (b.eye - b.target).length());
    assert!((da - db).abs() < 1e-6 * db, "the orbit keeps the distance");
    assert!((a.eye - b.eye).length() > 0.1 * db, "the camera orbited");
    // The screenshot is render's picture of the viewer's scene, exactly.
    let expected = render(&seen, "block-seen.png", &size);
    assert_eq!(differing_pixels(&shot, &expected, 0).0, 0);
}

/// `--peaks` with a block draws the peaks of every voxel of the block (counted here from
/// the peak image: a peak is a finite, non-zero triplet), with the glyphs or alone.
#[test]
fn a_block_draws_the_peaks_of_every_voxel() {
    let dir = fresh_dir("block-peaks");
    let coef = crate::common::dipy_data("func_coef.nii.gz");
    let peaks = dir.join("peaks.nii.gz");
    let run = glyphcast(&[
        "peaks",
        text(&coef),
        "--basis",
        "tournier07",
        "--legacy",
        "-o",
        text(&peaks),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let image = read_nifti(&peaks).expect("the peak image");
    let block = [0..2, 1..3, 1..4];
    let mut expected = 0;
    for k in block[2].clone() {
        for j in block[1].clone() {
            for i in block[0].clone() {
                let values: Vec<f64> = (0..image.data.shape()[3])
                    .map(|c| image.data[[i, j, k, c]])
                    .collect();
                expected += values
                    .chunks(3)
                    .filter(|p| p.iter().all(|v| v.is_finite()) && p.iter().any(|v| *v != 0.0))
                    .count();
            }
        }
    }
    assert!(
        expected > 12,
        "func_coef's crossings give several peaks a voxel"
    );
    let png = dir.join("peaks.png");
    let glyphs = ["--sh", text(&coef), "--basis", "tournier07", "--legacy"];
    for with_glyphs in [true, false] {
        let mut args = vec!["render", "--block", "--voxels", "0:2,1:3,1:4", "--peaks"];
        args.push(text(&peaks));
        if with_glyphs {
            args.extend(glyphs);
        }
        args.extend(["--width", "96", "-o", text(&png)]);
        let run = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{stderr}");
        let line = format!("peaks: {}: {expected} peaks drawn", coef.display());
        let line = if with_glyphs {
            line
        } else {
            format!("peaks: {}: {expected} peaks drawn", peaks.display())
        };
        assert!(stderr.contains(&line), "no '{line}' in:\n{stderr}");
        assert_eq!(
            stderr.contains("12 glyphs from 12 voxels"),
            with_glyphs,
            "{stderr}"
        );
    }
}
