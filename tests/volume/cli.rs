//! `glyphcast render --sh/--tensor` as a user meets it: bad input gives one error line
//! naming the file (and the field), a non-zero exit and no output at all, not even the
//! --save-scene file; good input renders (lavapipe) and saves the scene it rendered.
use super::fixtures::*;
use glam::DVec3;
use glyphcast::accuracy::compare_depth;
use glyphcast::demo::fibre_tensor;
use glyphcast::glyph::reference::reference_depth;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::scene::Scene;
use glyphcast_dmri::volume::{ImageRequest, VolumeKind, VolumeOptions, load_volume, volume_scene};
use ndarray::Array3;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn glyphcast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast")
}

fn text(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

/// Inputs in `DIR/in`, outputs asked for in `DIR/out`.
struct Case {
    inputs: PathBuf,
    outputs: PathBuf,
}

impl Case {
    fn new(name: &str) -> Self {
        let root = scratch(name);
        let case = Case {
            inputs: root.join("in"),
            outputs: root.join("out"),
        };
        std::fs::create_dir_all(&case.inputs).expect("inputs folder");
        std::fs::create_dir_all(&case.outputs).expect("outputs folder");
        case
    }

    fn input(&self, name: &str) -> PathBuf {
        self.inputs.join(name)
    }

    /// `render ARGS -o out.png --depth-out out.npy --save-scene scene.json` at 32 x 32.
    fn render(&self, args: &[&str]) -> Output {
        let png = self.outputs.join("out.png");
        let npy = self.outputs.join("out.npy");
        let scene = self.outputs.join("scene.json");
        let mut all = vec!["render"];
        all.extend(args);
        all.extend([
            "-o",
            text(&png),
            "--depth-out",
            text(&npy),
            "--save-scene",
            text(&scene),
            "--width",
            "32",
            "--height",
            "32",
        ]);
        glyphcast(&all)
    }

    /// Runs `args`, expects a clean failure and returns its one error line.
    fn expect_failure(&self, args: &[&str]) -> String {
        let out = self.render(args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(
            !out.status.success(),
            "{args:?}: expected failure:\n{stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: panic:\n{stderr}");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(
            errors.len(),
            1,
            "{args:?}: one error line expected:\n{stderr}"
        );
        let left: Vec<_> = std::fs::read_dir(&self.outputs).expect("listing").collect();
        assert!(left.is_empty(), "{args:?}: output left behind: {left:?}");
        errors[0].to_owned()
    }
}

const TENSOR_DIMS: [usize; 3] = [3, 4, 5];

/// A 3 x 4 x 5 DTI volume (qform with qfac -1) of ellipsoids with radius 1 along voxel
/// axis i or the ij diagonal and 0.5 across; `edit` may change any voxel.
fn write_tensor_volume(path: &Path, edit: impl Fn([usize; 3], Vec<f64>) -> Vec<f64>) {
    let data = volume(TENSOR_DIMS, 6, |v| {
        let axis = if (v[0] + v[1]) % 2 == 0 {
            DVec3::X
        } else {
            DVec3::new(1.0, 1.0, 0.0)
        };
        let mut t = fibre_tensor(2, &[(axis, 0.5)]);
        for slot in [0, 3, 5] {
            t[slot] += 0.5;
        }
        edit(v, t)
    });
    write4(path, Storage::QformFlipped, &data);
}

#[test]
fn every_bad_volume_input_fails_cleanly_naming_the_file() {
    let case = Case::new("cli-bad");
    let good = case.input("good.nii.gz");
    write_tensor_volume(&good, |_, c| c);
    let good = text(&good).to_owned();

    let missing = text(&case.input("missing.nii.gz")).to_owned();
    let not_nifti = case.input("notes.nii");
    std::fs::write(&not_nifti, "this is not a NIfTI file\n".repeat(30)).expect("writing");
    let short = case.input("short.nii");
    std::fs::write(&short, "tiny").expect("writing");
    let truncated = case.input("truncated.nii.gz");
    let bytes = std::fs::read(&good).expect("reading");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).expect("writing");
    let three_d = case.input("three_d.nii.gz");
    write_mask(&three_d, Storage::Sform, &Array3::ones((3, 4, 5)));
    let sh44 = case.input("sh44.nii.gz");
    write4(
        &sh44,
        Storage::Sform,
        &volume([2, 2, 2], 44, |_| vec![1.0; 44]),
    );
    let sh6 = case.input("sh6.nii.gz");
    write4(
        &sh6,
        Storage::Sform,
        &volume([2, 2, 2], 6, |_| vec![1.0; 6]),
    );
    let mask = case.input("mask_3x4x6.nii.gz");
    write_mask(&mask, Storage::Sform, &Array3::ones((3, 4, 6)));
    let all_nan = case.input("all_nan.nii.gz");
    write_tensor_volume(&all_nan, |_, _| vec![f64::NAN; 6]);
    let small_64d = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data/dipy/small_64D.nii");
    let scene = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/scenes/sphere.json");

    let (notes, short, truncated, three_d, sh44, sh6, mask, all_nan, small_64d, scene) = (
        text(&not_nifti),
        text(&short),
        text(&truncated),
        text(&three_d),
        text(&sh44),
        text(&sh6),
        text(&mask),
        text(&all_nan),
        text(&small_64d),
        text(&scene),
    );
    // (arguments, words the error line must contain)
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        (
            vec!["--tensor", &missing, "--order", "2"],
            vec!["missing.nii.gz"],
        ),
        (
            vec!["--tensor", notes, "--order", "2"],
            vec!["notes.nii", "NIfTI"],
        ),
        (
            vec!["--tensor", short, "--order", "2"],
            vec!["short.nii", "NIfTI"],
        ),
        (
            vec!["--tensor", truncated, "--order", "2"],
            vec!["truncated.nii.gz"],
        ),
        (
            vec!["--tensor", three_d, "--order", "2"],
            vec!["three_d.nii.gz", "dim", "3D"],
        ),
        (
            vec!["--sh", three_d, "--basis", "tournier07"],
            vec!["three_d.nii.gz", "3D"],
        ),
        (
            vec!["--sh", sh44, "--basis", "tournier07"],
            vec!["sh44.nii.gz", "dim[4]", "44"],
        ),
        (
            vec!["--tensor", sh6, "--order", "4"],
            vec!["sh6.nii.gz", "dim[4]", "15"],
        ),
        (
            vec!["--tensor", sh6, "--order", "2", "--nonsymmetric"],
            vec!["sh6.nii.gz", "dim[4]", "9"],
        ),
        (
            vec!["--tensor", small_64d, "--order", "2"],
            vec!["small_64D.nii", "65"],
        ),
        (vec!["--sh", sh6, "--basis", "fsl"], vec!["--basis", "fsl"]),
        (
            // The alias names the non-legacy basis.
            vec!["--sh", sh6, "--basis", "mrtrix", "--legacy"],
            vec!["--basis", "mrtrix"],
        ),
        (vec!["--sh", sh6], vec!["--basis"]),
        (
            vec!["--tensor", &good, "--order", "2", "--mask", mask],
            vec!["mask_3x4x6.nii.gz", "3x4x6", "3x4x5", "good.nii.gz"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--slice", "axial:5"],
            vec!["good.nii.gz", "axial", "dim[3]"],
        ),
        (
            // This volume's voxel axis i runs along world y: the coronal plane is constant
            // i, 3 voxels.
            vec!["--tensor", &good, "--order", "2", "--slice", "coronal:4"],
            vec!["good.nii.gz", "dim[1]", "coronal:4", "constant i"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--slice", "oblique:1"],
            vec!["--slice"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--voxels", "5:9,:,:"],
            vec!["good.nii.gz", "--voxels"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--voxels", "1:2,3"],
            vec!["--voxels"],
        ),
        (vec!["--tensor", &good], vec!["--order"]),
        (vec!["--tensor", &good, "--order", "0"], vec!["order"]),
        (
            vec!["--tensor", &good, "--order", "2", "--lmax", "2"],
            vec!["--lmax"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--norm", "max"],
            vec!["--norm"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--scale=-1"],
            vec!["--scale"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--scale", "0"],
            vec!["--scale"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--width", "0"],
            vec!["--width"],
        ),
        (
            vec!["--tensor", all_nan, "--order", "2"],
            vec!["all_nan.nii.gz", "no glyph"],
        ),
        (
            vec!["--tensor", &good, "--order", "2", "--method", "magic"],
            vec!["magic"],
        ),
        (
            vec!["--tensor", &good, "--sh", sh6, "--order", "2"],
            vec!["--sh", "--tensor"],
        ),
        (vec![scene, "--slice", "axial:1"], vec!["--slice"]),
    ];
    for (args, words) in cases {
        let line = case.expect_failure(&args);
        for word in words {
            assert!(
                line.contains(word),
                "{args:?}: expected '{word}' in: {line}"
            );
        }
    }
}

fn tensor_kind() -> VolumeKind {
    VolumeKind::Tensor(TensorLayout {
        order: 2,
        symmetry: Symmetry::Symmetric,
    })
}

#[test]
fn a_tensor_volume_renders_and_saves_the_scene_it_rendered() {
    let case = Case::new("cli-render");
    let path = case.input("dti.nii.gz");
    write_tensor_volume(&path, |_, c| c);
    let (slice, voxels) = ("axial:2", "1:3,0:2,:");
    let file = text(&path);
    let out = case.render(&[
        "--tensor", file, "--order", "2", "--slice", slice, "--voxels", voxels,
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    assert!(stderr.contains("4 glyphs from 4 voxels"), "{stderr}");

    let saved = Scene::load(&case.outputs.join("scene.json")).expect("the saved scene");
    let volume = load_volume(&path, tensor_kind()).expect("loading");
    let options = VolumeOptions {
        slice: slice.parse().expect("slice"),
        voxels: voxels.parse().expect("voxels"),
        image: ImageRequest {
            width: Some(32),
            height: Some(32),
            ..Default::default()
        },
        ..Default::default()
    };
    let expected = volume_scene(&volume, &options).expect("scene").scene;
    assert_eq!(saved, expected);

    let (w, h, _) = glyphcast::io::png::read_png_rgba8(&case.outputs.join("out.png")).expect("PNG");
    assert_eq!((w, h), (32, 32));
    let (shape, depth) =
        glyphcast::io::npy::read_npy_f32(&case.outputs.join("out.npy")).expect("depth map");
    assert_eq!(shape, vec![32, 32]);
    // The depth map is the saved scene's: same coverage and depths as the float64
    // reference of that scene, away from the silhouettes (the bar of depth_accuracy.rs).
    let sets = prepare_scene(&saved, 0.0).expect("preparing");
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    let reference = reference_depth(&world, &saved.camera, 32, 32);
    let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
    let c = compare_depth(&depth, &reference, 32, 32, scale);
    // Four glyphs at 32 x 32: about 60 pixels inside their silhouettes, 260 on them.
    assert!(c.covered > 40, "the glyphs are in view: {c}");
    assert!(
        c.holes == 0 && c.false_hits == 0 && c.median_error < 1e-3,
        "{c}"
    );
}

#[test]
fn nan_voxels_are_left_out_with_a_warning_and_perspective_renders() {
    let case = Case::new("cli-nan");
    let path = case.input("dti_nan.nii.gz");
    write_tensor_volume(&path, |v, c| if v[0] == 1 { vec![f64::NAN; 6] } else { c });
    let out = case.render(&["--tensor", text(&path), "--order", "2", "--perspective"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    // The middle axial slice has 3 x 4 voxels, 4 of them with i = 1.
    assert!(
        stderr.contains("warning: ") && stderr.contains("dti_nan.nii.gz: 4 voxel(s) with NaN"),
        "{stderr}"
    );
    let saved = Scene::load(&case.outputs.join("scene.json")).expect("the saved scene");
    assert_eq!(saved.glyph_sets[0].len(), 8);
    let (_, depth) =
        glyphcast::io::npy::read_npy_f32(&case.outputs.join("out.npy")).expect("depth");
    assert!(
        depth.iter().any(|d| !d.is_nan()),
        "the perspective view shows glyphs"
    );
}

#[test]
fn three_slices_render_and_the_saved_scene_holds_the_three_planes() {
    let case = Case::new("cli-slices");
    let path = case.input("dti.nii.gz");
    write_tensor_volume(&path, |_, c| c);
    let png = case.outputs.join("out.png");
    let scene = case.outputs.join("scene.json");
    let file = text(&path);
    let out = glyphcast(&[
        "render",
        "--tensor",
        file,
        "--order",
        "2",
        "--slices",
        "mid",
        "--width",
        "64",
        "-o",
        text(&png),
        "--save-scene",
        text(&scene),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    // 3 x 4 x 5 voxels, middles 1, 2, 2: 20 + 15 + 12 on the planes, less the 12 on two
    // planes' lines, plus the one on all three.
    assert!(stderr.contains("36 glyphs from 36 voxels"), "{stderr}");
    let (w, _, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("PNG");
    assert_eq!(w, 64);
    assert!(
        rgba.chunks(4).any(|p| p[..3] != rgba[..3]),
        "something drawn"
    );

    let saved = Scene::load(&scene).expect("the saved scene");
    let volume = load_volume(&path, tensor_kind()).expect("loading");
    let map = &volume.voxel_to_world;
    let middle = TENSOR_DIMS.map(|n| n / 2);
    assert_eq!(saved.glyph_sets.len(), 3);
    let mut all = Vec::new();
    for (axis, set) in saved.glyph_sets.iter().enumerate() {
        for center in &set.centers {
            let voxel = (0..TENSOR_DIMS.iter().product::<usize>())
                .map(|n| {
                    [
                        n % TENSOR_DIMS[0],
                        n / TENSOR_DIMS[0] % TENSOR_DIMS[1],
                        n / (TENSOR_DIMS[0] * TENSOR_DIMS[1]),
                    ]
                })
                .find(|v| {
                    let p = map.voxel_center(DVec3::from_array(v.map(|i| i as f64)));
                    (p - *center).length() < 1e-6
                })
                .expect("a glyph at a voxel centre");
            assert_eq!(voxel[axis], middle[axis], "set {axis}: {voxel:?}");
            all.push(voxel);
        }
    }
    let unique: std::collections::BTreeSet<_> = all.iter().collect();
    assert_eq!((unique.len(), all.len()), (36, 36));

    for done in [&png, &scene] {
        std::fs::remove_file(done).expect("clearing the outputs");
    }
    let both = case.expect_failure(&[
        "--tensor", file, "--order", "2", "--slice", "axial", "--slices", "mid",
    ]);
    assert!(
        both.contains("--slice ") && both.contains("--slices"),
        "{both}"
    );
}
