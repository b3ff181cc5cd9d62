//! Stiffness tensors from the command line: `glyphcast stiffness` turns a Voigt matrix
//! file into a scene, `glyphcast demo --stiffness` renders a field of copper crystals
//! (on lavapipe, with the validation layer), and the same field rendered in the library
//! matches the float64 reference.
use crate::common;
use common::text;
use glyphcast::demo::stiffness_demo_scene;
use glyphcast::glyph::Symmetry;
use glyphcast::render::RenderSettings;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::scene::{GlyphKind, Scene};
use std::path::PathBuf;
use std::process::{Command, Output};

const LAVAPIPE: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

fn glyphcast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .env("VK_DRIVER_FILES", LAVAPIPE)
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast")
}

/// A fresh folder for one test of this file.
fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("stiffness/{name}"))
}

const COPPER_CSV: &str = "# copper, GPa, standard Voigt order\n\
    168.4 121.4 121.4 0 0 0\n121.4 168.4 121.4 0 0 0\n121.4 121.4 168.4 0 0 0\n\
    0 0 0 75.4 0 0\n0 0 0 0 75.4 0\n0 0 0 0 0 75.4\n";

#[test]
fn stiffness_command_writes_a_one_glyph_scene() {
    let dir = fresh_dir("scene");
    let csv = dir.join("copper.csv");
    std::fs::write(&csv, COPPER_CSV).unwrap();
    for (name, extra, symmetry, count) in [
        ("full.json", vec![], Symmetry::NonSymmetric, 81),
        (
            "sym.json",
            vec!["--symmetric-part"],
            Symmetry::Symmetric,
            15,
        ),
        (
            "reversed.json",
            vec!["--shear-order", "12,13,23"],
            Symmetry::NonSymmetric,
            81,
        ),
    ] {
        let scene_path = dir.join(name);
        let mut args = vec!["stiffness", text(&csv), "-o", text(&scene_path)];
        args.extend(extra);
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let scene = Scene::load(&scene_path).expect("the written scene loads");
        let set = &scene.glyph_sets[0];
        let GlyphKind::Tensor(layout) = set.kind else {
            panic!("{name}: a tensor glyph set");
        };
        assert_eq!((layout.order, layout.symmetry), (4, symmetry), "{name}");
        assert_eq!(set.coeffs[0].len(), count, "{name}");
        if count == 81 {
            // C_1111 is the first entry; copper is cubic, so the shear order does not
            // change it (the diagonal shear entries are all C44).
            assert_eq!(set.coeffs[0][0], 168.4);
            // C_2323: indices (1, 2, 1, 2), row major.
            assert_eq!(set.coeffs[0][27 + 2 * 9 + 3 + 2], 75.4);
        }
    }
}

#[test]
fn stiffness_command_rejects_bad_files() {
    let dir = fresh_dir("bad");
    let out_dir = fresh_dir("bad-out");
    let output = out_dir.join("scene.json");
    let cases = [
        (
            "five_rows.csv",
            COPPER_CSV.lines().take(6).collect::<Vec<_>>().join("\n"),
            "rows",
        ),
        (
            "asymmetric.csv",
            COPPER_CSV.replacen("121.4", "120", 1),
            "C12",
        ),
        ("nan.csv", COPPER_CSV.replacen("75.4", "nan", 1), "C44"),
        (
            "word.csv",
            COPPER_CSV.replacen("168.4", "hard", 1),
            "'hard'",
        ),
        ("zero.csv", "0 0 0 0 0 0\n".repeat(6), "zero"),
        ("bad.json", "{\"voigt\": [[1, 2]]}".to_string(), "voigt"),
    ];
    for (name, content, word) in cases {
        let input = dir.join(name);
        std::fs::write(&input, content).unwrap();
        let out = glyphcast(&["stiffness", text(&input), "-o", text(&output)]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{name}: expected failure");
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{name}: {stderr}");
        assert!(
            errors[0].contains(name) && errors[0].contains(word),
            "{name}: {}",
            errors[0]
        );
        assert_eq!(
            std::fs::read_dir(&out_dir).unwrap().count(),
            0,
            "{name}: no output"
        );
    }
    let input = dir.join("good.csv");
    std::fs::write(&input, COPPER_CSV).unwrap();
    let out = glyphcast(&[
        "stiffness",
        text(&input),
        "-o",
        text(&output),
        "--shear-order",
        "1,2,3",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--shear-order"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&out_dir).unwrap().count(), 0);
}

#[test]
fn demo_stiffness_renders() {
    let dir = fresh_dir("demo");
    let png = dir.join("x.png");
    let out = glyphcast(&[
        "demo",
        "--stiffness",
        "-o",
        text(&png),
        "--width",
        "64",
        "--height",
        "64",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (w, h, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("demo PNG");
    assert_eq!((w, h), (64, 64));
    let background = &rgba[0..4];
    let drawn = rgba.chunks_exact(4).filter(|p| *p != background).count();
    assert!(drawn > 64 * 64 / 8, "only {drawn} pixels drawn:\n{stderr}");
}

#[test]
fn stiffness_demo_matches_the_float64_reference() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let mut scene = stiffness_demo_scene();
    assert_eq!(scene.glyph_sets[0].len(), 25);
    assert!(scene.glyph_sets[0].coeffs.iter().all(|c| c.len() == 81));
    (scene.image.width, scene.image.height) = (120, 108);
    let rendered =
        common::render_and_compare(&gpu, &mut renderer, &scene, &RenderSettings::default());
    let c = &rendered.comparison;
    eprintln!("stiffness demo: {c:?}");
    if c.holes > 0 || c.false_hits > 0 || c.median_error > 1e-3 {
        common::save_failure_images("stiffness-demo", &rendered);
    }
    assert!(c.covered > 1000, "glyphs cover the image: {c:?}");
    // The bar of tests/depth_accuracy.rs: no holes, no false hits away from the
    // silhouette band, median depth error below 1e-3 of the glyph scale.
    assert_eq!((c.holes, c.false_hits), (0, 0), "{c:?}");
    assert!(c.median_error < 1e-3, "{c:?}");
}
