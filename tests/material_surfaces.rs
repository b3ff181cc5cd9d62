//! The surfaces of `glyphcast stiffness --surface`, drawn on lavapipe with the validation
//! layer, against two float64 references, on crystals no other test holds: a trigonal
//! crystal (calcite), a model tetragonal crystal that is auxetic and expands along c
//! under pressure (negative linear compressibility), and a cubic crystal (alpha iron)
//! turned by Bunge angles.
//!
//! Each scene goes through the command line (`stiffness` writes it, `render` draws it and
//! writes the depth map), then:
//!
//! 1. the renderer's float64 reference (`glyph::reference`, the exact intersection of
//!    the same scene, reciprocal glyphs included): no holes, no false hits away from the
//!    silhouette band, median depth error at most 1e-4 of the glyph's size;
//! 2. the materials crate's moduli (`Stiffness::radius`, computed from the matrix without
//!    any of the renderer's code): every drawn point p lies on the surface
//!    |p| = k |r(p / |p|)| for one k, the scene's scale: its spread
//!    max | |p| - k |r| | / (k max |r|) is at most 2e-3 (measured: 8.6e-7 to 5.8e-6),
//!    and k is the scene's scale to 1e-3 (measured: 3.2e-7).
use crate::common;
use common::text;
use glyphcast::accuracy::compare_depth;
use glyphcast::glyph::reference::reference_depth;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::scene::Scene;
use glyphcast_materials::{Rotation, Stiffness, Surface};
use std::path::Path;

const SIZE: u32 = 160;

/// Calcite (CaCO3), trigonal class -3m, GPa: C11 = 149.4, C33 = 85.2, C44 = 34.1,
/// C12 = 57.9, C13 = 53.5, C14 = -20.0, C66 = (C11 - C12) / 2 (near Chen et al., 2001).
const CALCITE: &str = "149.4 57.9 53.5 -20.0 0 0\n57.9 149.4 53.5 20.0 0 0\n\
    53.5 53.5 85.2 0 0 0\n-20.0 20.0 0 34.1 0 0\n0 0 0 0 34.1 -20.0\n0 0 0 0 -20.0 45.75\n";

/// A model tetragonal crystal, GPa: C11 = 89.8, C33 = 96.8, C44 = 49.8, C66 = 57.1,
/// C12 = 36.6, C13 = 71.5. Positive definite, auxetic (Poisson's ratio down to about
/// -0.7) and with a negative linear compressibility along c (about -0.0083 / GPa).
const AUXETIC_TETRAGONAL: &str = "89.8 36.6 71.5 0 0 0\n36.6 89.8 71.5 0 0 0\n\
    71.5 71.5 96.8 0 0 0\n0 0 0 49.8 0 0\n0 0 0 0 49.8 0\n0 0 0 0 0 57.1\n";

/// Alpha iron (cubic), GPa: C11 = 231.4, C12 = 134.7, C44 = 116.4.
const IRON: &str = "231.4 134.7 134.7 0 0 0\n134.7 231.4 134.7 0 0 0\n\
    134.7 134.7 231.4 0 0 0\n0 0 0 116.4 0 0\n0 0 0 0 116.4 0\n0 0 0 0 0 116.4\n";

/// The crystals: name, matrix file, Bunge angles in degrees if turned.
const CRYSTALS: [(&str, &str, Option<[f64; 3]>); 3] = [
    ("calcite", CALCITE, None),
    ("auxetic-tetragonal", AUXETIC_TETRAGONAL, None),
    ("iron-turned", IRON, Some([30.0, 40.0, 50.0])),
];

/// The matrix of a whitespace-separated file as the materials crate takes it.
fn matrix(content: &str) -> [[f64; 6]; 6] {
    let values: Vec<f64> = content
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    std::array::from_fn(|i| std::array::from_fn(|j| values[6 * i + j]))
}

/// What one surface of one crystal measured.
struct Measured {
    covered: usize,
    /// Drawn points where the modulus is negative.
    negative: usize,
    spread: f64,
    scale_error: f64,
}

/// Writes, draws and checks `surface` of one crystal (see the module notes).
fn check_surface(name: &str, content: &str, euler: Option<[f64; 3]>, surface: Surface) -> Measured {
    let label = format!("{name}-{}", surface.name());
    let dir = common::fresh_dir(&format!("material_surfaces/{label}"));
    let input = dir.join(format!("{name}.txt"));
    std::fs::write(&input, content).unwrap();
    let scene_path = dir.join("scene.json");
    let angles = euler.map(|[a, b, c]| format!("{a},{b},{c}"));
    let mut args = vec![
        "stiffness",
        text(&input),
        "--surface",
        surface.name(),
        "-o",
        text(&scene_path),
    ];
    if let Some(angles) = &angles {
        args.extend(["--euler", angles]);
    }
    run(&args);
    // The glyph fills the frame (largest radius 1 in the world), however small it is
    // against the scale that the material's other surface of a pair shares with it.
    let mut written = Scene::load(&scene_path).expect("the written scene loads");
    let sets = prepare_scene(&written, 0.0).expect("preparing the scene");
    let radius = glyphcast::render::glyph_data::largest_radius(&sets[0].world);
    written.glyph_sets[0].scales[0] /= radius;
    std::fs::write(&scene_path, written.to_json()).unwrap();
    let png = dir.join("surface.png");
    let depth_path = dir.join("depth.npy");
    let side = SIZE.to_string();
    run(&[
        "render",
        text(&scene_path),
        "-o",
        text(&png),
        "--depth-out",
        text(&depth_path),
        "--width",
        &side,
        "--height",
        &side,
        "--color",
        "sign",
    ]);
    let scene = Scene::load(&scene_path).expect("the written scene loads");
    let (shape, depth) = glyphcast::io::npy::read_npy_f32(&depth_path).expect("depth map");
    assert_eq!(shape, [SIZE as usize, SIZE as usize]);

    // 1. The renderer's float64 reference.
    let sets = prepare_scene(&scene, 0.0).expect("preparing the scene");
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    assert_eq!(world.len(), 1, "{label}: one glyph");
    let reference = reference_depth(&world, &scene.camera, SIZE, SIZE);
    let size = world[0].scale * world[0].bound;
    let c = compare_depth(&depth, &reference, SIZE as usize, SIZE as usize, size);
    eprintln!("{label}: {c}");
    assert!(
        c.covered > (SIZE * SIZE / 20) as usize,
        "{label}: too little drawn: {c}"
    );
    assert_eq!((c.holes, c.false_hits), (0, 0), "{label}: {c}");
    assert!(c.median_error <= 1e-4, "{label}: {c}");

    // 2. The materials crate's moduli.
    let mut stiffness = Stiffness::new(matrix(content)).expect("a stable crystal");
    if let Some([a, b, c]) = euler {
        stiffness = stiffness.rotated(&Rotation::from_bunge_degrees(a, b, c).unwrap());
    }
    let center = scene.glyph_sets[0].centers[0];
    let scale = scene.glyph_sets[0].scales[0];
    let (_, _, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("the PNG");
    let mut points = Vec::new();
    // The signed modulus at each drawn point, and whether its pixel has the negative
    // colour of --color sign (blue: more blue than red).
    let mut signs = Vec::new();
    for j in 0..SIZE {
        for i in 0..SIZE {
            let t = depth[(j * SIZE + i) as usize];
            if t.is_nan() {
                continue;
            }
            let ray = scene.camera.ray(i, j, SIZE, SIZE);
            let q = ray.origin + f64::from(t) * ray.dir - center;
            let signed = stiffness.radius(surface, q.to_array()).unwrap();
            points.push((q.length(), signed.abs()));
            let pixel = &rgba[4 * (j * SIZE + i) as usize..][..3];
            signs.push((signed, pixel[2] > pixel[0]));
        }
    }
    let largest = points.iter().map(|p| p.1).fold(0.0, f64::max);
    // Every pixel whose modulus is clearly signed (at least 2 % of the largest, away
    // from the cones where it changes sign) has that sign's colour.
    let wrong_sign = signs
        .iter()
        .filter(|(signed, blue)| signed.abs() >= 0.02 * largest && (*signed < 0.0) != *blue)
        .count();
    let negative = signs.iter().filter(|(signed, _)| *signed < 0.0).count();
    eprintln!("{label}: {negative} negative points, {wrong_sign} in the wrong colour");
    assert_eq!(wrong_sign, 0, "{label}: pixels in the other sign's colour");
    let mut ratios: Vec<f64> = points
        .iter()
        .filter(|p| p.1 > 0.1 * largest)
        .map(|p| p.0 / p.1)
        .collect();
    ratios.sort_by(f64::total_cmp);
    let k = ratios[ratios.len() / 2];
    let spread = points
        .iter()
        .map(|&(length, r)| (length - k * r).abs())
        .fold(0.0, f64::max)
        / (k * largest);
    let scale_error = (k / scale - 1.0).abs();
    eprintln!(
        "{label}: {} drawn points, k / scale - 1 = {:.2e}, spread {spread:.2e}",
        points.len(),
        k / scale - 1.0
    );
    assert!(spread <= 2e-3, "{label}: spread {spread:.3e}");
    assert!(scale_error <= 1e-3, "{label}: scale {k} against {scale}");
    Measured {
        covered: c.covered,
        negative,
        spread,
        scale_error,
    }
}

/// Runs the command line and asserts success.
fn run(args: &[&str]) {
    let out = common::glyphcast(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "glyphcast {args:?}:\n{stderr}");
    assert!(!stderr.contains("VUID"), "validation: {stderr}");
}

fn check_every_crystal(surface: Surface) {
    for (name, content, euler) in CRYSTALS {
        let m = check_surface(name, content, euler, surface);
        assert!(m.covered > 0 && m.spread.is_finite() && m.scale_error.is_finite());
    }
}

#[test]
fn young_surfaces_lie_on_the_moduli() {
    check_every_crystal(Surface::Young);
}

#[test]
fn compressibility_surfaces_lie_on_the_moduli() {
    check_every_crystal(Surface::Compressibility);
}

/// A scene of one reciprocal glyph set: `order`, `negative`, coefficients of a symmetric
/// tensor whose x^n, y^n and z^n entries are 1 (the others 0).
fn reciprocal_scene(order: u32, negative: &str) -> String {
    let count = ((order + 1) * (order + 2) / 2) as usize;
    let mut coeffs = vec![0.0; count];
    // Lexicographic sorted tuples: 0...0 first, 1...1 at count - order - 1, 2...2 last.
    for k in [0, count - order as usize - 1, count - 1] {
        coeffs[k] = 1.0;
    }
    format!(
        r#"{{"version": 1, "glyphs": [{{"kind": "tensor", "order": {order}, "negative": "{negative}",
        "shape": "reciprocal", "centers": [[0, 0, 0]], "scale": 1, "coeffs": [{coeffs:?}]}}],
        "camera": {{"eye": [3, -4, 2], "target": [0, 0, 0]}}, "image": {{"width": 32, "height": 32}}}}"#
    )
}

/// What the reciprocal glyph cannot be drawn with is refused with exit status 1 (2 for
/// the compute path), one error naming the setting or the field, and no output: other
/// methods, the compute path,
/// an offset, hidden lobes, an odd order (f changes sign: 1/|f| is unbounded); and
/// `stiffness` refuses Young's surface of an unstable crystal whose 1/E vanishes,
/// naming the file, and --symmetric-part with a surface.
#[test]
fn what_the_reciprocal_glyph_cannot_take_is_refused() {
    let dir = common::fresh_dir("material_surfaces/refusals");
    let out = common::fresh_dir("material_surfaces/refusals-out");
    let good = dir.join("good.json");
    std::fs::write(&good, reciprocal_scene(4, "abs")).unwrap();
    let png = out.join("x.png");
    let render = |scene: &Path, extra: &[&str], words: &[&str]| {
        let mut args = vec!["render", text(scene), "-o", text(&png)];
        args.extend(extra);
        common::expect_failure(&args, &out, words);
    };
    render(&good, &["--method", "fixed"], &["reciprocal", "fixed"]);
    render(
        &good,
        &["--method", "interval"],
        &["reciprocal", "interval"],
    );
    // (A path the glyphs cannot take is a refusal of the command line: exit 2.)
    common::expect_usage_failure(
        &["render", text(&good), "-o", text(&png), "--path", "compute"],
        &out,
        &["reciprocal", "compute"],
    );
    render(
        &good,
        &["--method", "fixed", "--offset", "0.1"],
        &["reciprocal", "offset"],
    );
    let hide = dir.join("hide.json");
    std::fs::write(&hide, reciprocal_scene(4, "hide")).unwrap();
    render(&hide, &[], &["hide.json", "glyphs[0].shape", "negative"]);
    let odd = dir.join("odd.json");
    std::fs::write(&odd, reciprocal_scene(3, "abs")).unwrap();
    render(
        &odd,
        &[],
        &["odd.json: glyphs[0]: glyph 0", "least |f|", "unbounded"],
    );
    // The scene itself draws.
    run(&["render", text(&good), "-o", text(&png)]);
    std::fs::remove_file(&png).unwrap();

    // An unstable crystal (C12 > C11: negative in the (1, -1, 0) strain) whose 1/E
    // changes sign.
    let unstable = dir.join("unstable.txt");
    std::fs::write(
        &unstable,
        "100 150 0 0 0 0\n150 100 0 0 0 0\n0 0 100 0 0 0\n0 0 0 50 0 0\n0 0 0 0 50 0\n\
         0 0 0 0 0 50\n",
    )
    .unwrap();
    let scene = out.join("scene.json");
    let args = [
        "stiffness",
        text(&unstable),
        "--allow-unstable",
        "--surface",
        "young",
        "-o",
        text(&scene),
    ];
    common::expect_failure(&args, &out, &["unstable.txt", "unbounded"]);
    let input = dir.join("iron.txt");
    std::fs::write(&input, IRON).unwrap();
    let args = [
        "stiffness",
        text(&input),
        "--surface",
        "young",
        "--symmetric-part",
        "-o",
        text(&scene),
    ];
    let run = common::glyphcast(&args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && stderr.contains("--symmetric-part"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 0);
}

/// Alpha quartz (SiO2), trigonal class 32, GPa: C11 = 86.6, C33 = 106.1, C44 = 57.8,
/// C12 = 6.7, C13 = 12.6, C14 = -17.8, C66 = (C11 - C12) / 2 (near Heyliger et al.,
/// 2003).
const QUARTZ: &str = "86.6 6.7 12.6 -17.8 0 0\n6.7 86.6 12.6 17.8 0 0\n\
    12.6 12.6 106.1 0 0 0\n-17.8 17.8 0 57.8 0 0\n0 0 0 0 57.8 -17.8\n0 0 0 0 -17.8 39.95\n";

/// Alpha cristobalite (SiO2), tetragonal, GPa: C11 = 59.4, C33 = 42.4, C44 = 67.2,
/// C66 = 25.7, C12 = 3.8, C13 = -4.4 (Yeganeh-Haeri et al., 1992): auxetic.
const CRISTOBALITE: &str = "59.4 3.8 -4.4 0 0 0\n3.8 59.4 -4.4 0 0 0\n\
    -4.4 -4.4 42.4 0 0 0\n0 0 0 67.2 0 0\n0 0 0 0 67.2 0\n0 0 0 0 0 25.7\n";

/// Copper (cubic), GPa: C11 = 168.4, C12 = 121.4, C44 = 75.4: its two shear surfaces
/// touch along the cube axes and the body diagonals, where every v ⊥ u shears alike.
const COPPER: &str = "168.4 121.4 121.4 0 0 0\n121.4 168.4 121.4 0 0 0\n\
    121.4 121.4 168.4 0 0 0\n0 0 0 75.4 0 0\n0 0 0 0 75.4 0\n0 0 0 0 0 75.4\n";

/// The crystals of the shear surfaces, none of which the other surfaces' tests hold.
const SHEAR_CRYSTALS: [(&str, &str, Option<[f64; 3]>); 3] = [
    ("quartz", QUARTZ, None),
    ("cristobalite", CRISTOBALITE, None),
    ("copper-turned", COPPER, Some([20.0, 35.0, 65.0])),
];

#[test]
fn shear_surfaces_lie_on_the_moduli() {
    for surface in [Surface::ShearMin, Surface::ShearMax] {
        for (name, content, euler) in SHEAR_CRYSTALS {
            let m = check_surface(name, content, euler, surface);
            assert!(m.covered > 0 && m.spread.is_finite() && m.scale_error.is_finite());
        }
    }
}

/// Poisson's ratio's extremes over v ⊥ u (ratio glyphs, degree 18 along a ray) on the
/// same crystals; the auxetic cristobalite's smallest ratio is negative in most
/// directions and drawn in the negative colour.
#[test]
fn poisson_surfaces_lie_on_the_ratios() {
    for surface in [Surface::PoissonMin, Surface::PoissonMax] {
        for (name, content, euler) in SHEAR_CRYSTALS {
            let m = check_surface(name, content, euler, surface);
            assert!(m.covered > 0 && m.spread.is_finite() && m.scale_error.is_finite());
            if (name, surface) == ("cristobalite", Surface::PoissonMin) {
                assert!(
                    m.negative > m.covered / 2,
                    "{name}: {} negative",
                    m.negative
                );
            }
        }
    }
}

/// What the shear and Poisson surfaces cannot be drawn with is refused with exit status
/// 1 (2 for the compute path), one error naming the plane or ratio glyphs and the
/// setting, and no output: the
/// other methods, the compute path, an offset.
#[test]
fn what_the_shear_and_poisson_surfaces_cannot_take_is_refused() {
    let dir = common::fresh_dir("material_surfaces/shear-refusals");
    let out = common::fresh_dir("material_surfaces/shear-refusals-out");
    let input = dir.join("quartz.txt");
    std::fs::write(&input, QUARTZ).unwrap();
    for (surface, glyphs) in [("shear-max", "plane"), ("poisson-min", "ratio")] {
        let scene = dir.join(format!("{surface}.json"));
        run(&[
            "stiffness",
            text(&input),
            "--surface",
            surface,
            "-o",
            text(&scene),
        ]);
        let png = out.join("x.png");
        let render = |extra: &[&str], words: &[&str]| {
            let mut args = vec!["render", text(&scene), "-o", text(&png)];
            args.extend(extra);
            common::expect_failure(&args, &out, words);
        };
        render(&["--method", "fixed"], &[glyphs, "fixed"]);
        render(&["--method", "affine"], &[glyphs, "affine"]);
        common::expect_usage_failure(
            &[
                "render",
                text(&scene),
                "-o",
                text(&png),
                "--path",
                "compute",
            ],
            &out,
            &[glyphs, "compute"],
        );
        render(
            &["--method", "fixed", "--offset", "0.1"],
            &[glyphs, "offset"],
        );
        // The scene itself draws.
        run(&["render", text(&scene), "-o", text(&png)]);
        std::fs::remove_file(&png).unwrap();
    }
    // A ratio glyph whose Q vanishes on the sphere (Q = x⁴, zero along y and z) has an
    // unbounded surface: refused, naming the glyph set, the glyph and Q.
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("poisson-min.json")).unwrap())
            .unwrap();
    let coeffs = doc["glyphs"][0]["coeffs"][0].as_array_mut().unwrap();
    let q_first = coeffs.len() - 15;
    for (k, c) in coeffs[q_first..].iter_mut().enumerate() {
        *c = serde_json::json!(if k == 0 { 1.0 } else { 0.0 });
    }
    let vanishing = dir.join("vanishing-q.json");
    std::fs::write(&vanishing, doc.to_string()).unwrap();
    let png = out.join("x.png");
    // Named with the file and its field, by render, bench and view alike (the viewer
    // prepares the glyphs before it opens a window).
    let named = format!(
        "{}: glyphs[0]: glyph 0: guaranteed least Q",
        text(&vanishing)
    );
    for command in [
        vec!["render", text(&vanishing), "-o", text(&png)],
        vec!["bench", text(&vanishing), "--quick"],
        vec!["view", text(&vanishing), "--frames", "1"],
    ] {
        common::expect_failure(&command, &out, &[&named, "positive in every direction"]);
    }
}
