//! Shared test helpers: a validated GPU, rendering against the float64 reference, and
//! failure images a person can look at.
#![allow(dead_code)]
use glyphcast::accuracy::{DepthComparison, compare_depth};
use glyphcast::glyph::reference::reference_depth;
use glyphcast::render::RenderSettings;
use glyphcast::render::glyph_data::{GlyphSetData, prepare_scene};
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::scene::Scene;
use glyphcast::vk::{Gpu, GpuOptions};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub mod dwi;
pub mod nifti;
pub mod underlay;
pub mod window;

// The test modules use only some of these names.
#[allow(unused_imports)]
pub use dwi::{
    DwiFiles, axis_angle, fit_dti_small_64d, fit_small_64d, largest_difference, numbers,
};

/// A GPU with the validation layer on (tests never run without it). The device is the
/// one GLYPHCAST_DEVICE names, else the best available: lavapipe in CI.
pub fn gpu() -> Gpu {
    let options = GpuOptions {
        validation: true,
        device: std::env::var("GLYPHCAST_DEVICE").ok(),
    };
    let gpu = Gpu::headless(&options).expect("creating a Vulkan device with validation");
    assert!(
        gpu.validation_enabled(),
        "validation layer must be on in tests"
    );
    gpu
}

pub struct Rendered {
    pub sets: Vec<GlyphSetData>,
    pub image: RenderedImage,
    pub reference: Vec<f64>,
    pub comparison: DepthComparison,
    /// The largest world bounding radius: the glyph scale errors are measured in.
    pub scale: f64,
}

pub fn output_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("test-output");
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// Renders `scene` on the GPU and in float64, compares depth, and writes the rendered
/// image, a reference image and a difference image when `name` fails later.
pub fn render_and_compare(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    scene: &Scene,
    settings: &RenderSettings,
) -> Rendered {
    render_and_compare_with(gpu, renderer, scene, settings, |_| {})
}

/// [`render_and_compare`] with the prepared sets changed by `prepare` before the render
/// (the pieces added, for one).
pub fn render_and_compare_with(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    scene: &Scene,
    settings: &RenderSettings,
    prepare: impl FnOnce(&mut Vec<GlyphSetData>),
) -> Rendered {
    let mut sets = prepare_scene(scene, settings.offset as f64).expect("preparing the scene");
    prepare(&mut sets);
    let (w, h) = (scene.image.width, scene.image.height);
    let image = renderer
        .render_view(
            gpu,
            &sets,
            &glyphcast::FrameView::new(&scene.camera, w, h),
            settings,
        )
        .expect("rendering");
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    let reference = reference_depth(&world, &scene.camera, w, h);
    let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
    let comparison = compare_depth(&image.distance, &reference, w as usize, h as usize, scale);
    Rendered {
        sets,
        image,
        reference,
        comparison,
        scale,
    }
}

/// Pixels whose ray distances differ in any bit between two renders of one size.
pub fn differing_distances(a: &RenderedImage, b: &RenderedImage) -> usize {
    a.distance
        .iter()
        .zip(&b.distance)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

/// Writes the render, the reference coverage and a map of holes (red) and false hits
/// (blue) as PNGs, so a failing test leaves something to look at.
pub fn save_failure_images(name: &str, r: &Rendered) {
    let dir = output_dir();
    let (w, h) = (r.image.width, r.image.height);
    let _ = glyphcast::io::png::write_png_rgba8(
        &dir.join(format!("{name}-actual.png")),
        w,
        h,
        &r.image.rgba,
    );
    let mut diff = Vec::with_capacity(r.reference.len() * 4);
    for (&d, &e) in r.image.distance.iter().zip(&r.reference) {
        let px = match (d.is_nan(), e.is_nan()) {
            (true, false) => [255, 0, 0, 255],
            (false, true) => [0, 0, 255, 255],
            (false, false) => [200, 200, 200, 255],
            (true, true) => [0, 0, 0, 255],
        };
        diff.extend_from_slice(&px);
    }
    let _ = glyphcast::io::png::write_png_rgba8(&dir.join(format!("{name}-diff.png")), w, h, &diff);
    eprintln!("{name}: images in {}", dir.display());
}

/// The sRGB encoding of a linear value as an 8-bit colour target stores it, in steps of
/// 1/255 (unrounded).
pub fn srgb_byte(linear: f64) -> f64 {
    let c = linear.clamp(0.0, 1.0);
    let encoded = if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    encoded * 255.0
}

/// Runs the glyphcast binary with the validation layer on.
pub fn glyphcast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast")
}

/// Writes `data` (first three axes spatial) as a float32 NIfTI-1 file whose sform
/// (code 1, scanner) is `affine`, with an empty description, through glyphcast's own
/// writer (gzip-compressed when the name ends in `.gz`).
pub fn write_nifti(path: &Path, data: &ndarray::ArrayD<f64>, affine: glam::DMat4) {
    let linear = glam::DMat3::from_mat4(affine);
    let row = |r: usize| affine.row(r).to_array();
    let lengths = [linear.x_axis, linear.y_axis, linear.z_axis].map(|c| c.length());
    let header = glyphcast_dmri::io::nifti::NiftiHeader {
        pixdim: [1.0, lengths[0], lengths[1], lengths[2], 1.0, 1.0, 1.0, 1.0],
        sform_code: 1,
        qform_code: 0,
        srow_x: row(0),
        srow_y: row(1),
        srow_z: row(2),
        ..Default::default()
    };
    let gzip = path.extension().is_some_and(|e| e == "gz");
    let name = path.display().to_string();
    let bytes = glyphcast_dmri::io::nifti::write::nifti1_bytes(&header, data.view(), gzip, &name)
        .expect("encoding a test NIfTI");
    std::fs::write(path, bytes).expect("writing a test NIfTI");
}

/// `data` reversed along its first (x) axis, and the affine of the same world grid for
/// it: the x column negated, the origin moved to the old last column (i' = n - 1 - i).
pub fn flipped_in_x(
    data: &ndarray::ArrayD<f64>,
    affine: glam::DMat4,
) -> (ndarray::ArrayD<f64>, glam::DMat4) {
    let n = data.shape()[0] as f64;
    let mut flipped = data.clone();
    flipped.invert_axis(ndarray::Axis(0));
    let mut flipped_affine = affine;
    flipped_affine.w_axis += affine.x_axis * (n - 1.0);
    flipped_affine.x_axis = -affine.x_axis;
    (flipped, flipped_affine)
}

/// A path as the `&str` a command line takes (test paths are UTF-8).
pub fn text(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

/// A fresh, empty folder under the test output folder.
pub fn fresh_dir(name: &str) -> PathBuf {
    let dir = output_dir().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creating a test folder");
    dir
}

/// A file of the test data (`tests/data/<folder>/<name>`).
pub fn test_data(folder: &str, name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data")
        .join(folder)
        .join(name)
}

/// A file of the DIPY test data (tests/data/dipy).
pub fn dipy_data(name: &str) -> PathBuf {
    test_data("dipy", name)
}

/// Runs `args` (writing into `out_dir`); expects exit code 1 (bad data), no panic, one
/// `error:` line holding every word of `words`, and nothing in `out_dir`. Returns the line.
pub fn expect_failure(args: &[&str], out_dir: &Path, words: &[&str]) -> String {
    expect_exit(args, out_dir, words, 1)
}

/// [`expect_failure`] for a refusal of the command line itself (exit code 2: options the
/// method, path or glyphs cannot take).
pub fn expect_usage_failure(args: &[&str], out_dir: &Path, words: &[&str]) -> String {
    expect_exit(args, out_dir, words, 2)
}

fn expect_exit(args: &[&str], out_dir: &Path, words: &[&str], code: i32) -> String {
    let run = glyphcast(args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(code), "{args:?}:\n{stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: panic:\n{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(
        errors.len(),
        1,
        "{args:?}: one error line expected:\n{stderr}"
    );
    for word in words {
        assert!(
            errors[0].contains(word),
            "{args:?}: '{word}' not in: {}",
            errors[0]
        );
    }
    let leftovers: Vec<_> = std::fs::read_dir(out_dir).expect("listing").collect();
    assert!(
        leftovers.is_empty(),
        "{args:?}: output left behind: {leftovers:?}"
    );
    errors[0].to_string()
}

/// DIPY's small_64D fitted as a DIPY user does (`glyphcast fit --odf csd --csd-algorithm
/// dipy --order 8 --basis dipy`), once per test run: the path of the SH volume.
pub fn dipy_csd_fit() -> PathBuf {
    static FIT: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    FIT.get_or_init(|| {
        let fit = fresh_dir("dipy-csd-fit").join("csd.nii.gz");
        let model = [
            "--odf",
            "csd",
            "--csd-algorithm",
            "dipy",
            "--order",
            "8",
            "--basis",
            "dipy",
        ];
        let out = fit_small_64d(&[&model[..], &["--quiet"]].concat(), &fit);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        fit
    })
    .clone()
}
