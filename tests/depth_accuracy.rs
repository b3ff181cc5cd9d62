//! Rendered depth maps against the float64 reference (exact ray-polynomial roots) on the
//! scenes where fixed-step ray casting is known to struggle: thin crossing lobes, a
//! slightly tilted copy of a glyph (the seed's Fig. 1), glyphs that touch their centre,
//! order 12, a non-symmetric order-4 stiffness tensor, and negative lobes shown and hidden.
//!
//! Every scene, with each method: zero holes and zero false hits away from a one-pixel
//! silhouette band, and a median depth error below 1e-3 of the glyph scale for `fixed` at
//! its default settings, below 1e-4 for `exact` (which is a root finder, so it is held to
//! the tighter bound; it measures ~2e-7, float32 rounding).
mod common;
use glam::{DMat3, DVec3};
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::{NegativeMode, Symmetry, TensorLayout};
use glyphcast::io::scene::{GlyphKind, ImageSize, Scene};
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::{Method, Refinement, RenderSettings};

use std::time::Instant;

const SIZE: u32 = 160;

fn camera(eye: DVec3) -> Camera {
    Camera {
        projection: Projection::Perspective { fov_y_deg: 30.0 },
        eye,
        target: DVec3::ZERO,
        up: DVec3::Z,
    }
}

fn scene(sets: Vec<glyphcast::io::scene::GlyphSet>, eye: DVec3) -> Scene {
    Scene {
        glyph_sets: sets,
        camera: camera(eye),
        image: ImageSize {
            width: SIZE,
            height: SIZE,
        },
    }
}

/// Two populations at 50 degrees, order 10: lobes a few pixels wide.
fn thin_crossing_lobes() -> Scene {
    let t = fibre_tensor(
        10,
        &[(direction(0.0, 0.0), 1.0), (direction(50.0, 10.0), 0.9)],
    );
    scene(
        vec![glyph_set(symmetric(10), vec![DVec3::ZERO], 1.0, vec![t])],
        DVec3::new(0.5, -1.0, 4.5),
    )
}

/// The same order-8 glyph twice, the second turned by 2 degrees about a skew axis.
fn tilted_copy() -> Scene {
    let fibres = [(direction(20.0, 0.0), 1.0), (direction(110.0, 0.0), 1.0)];
    let turn = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 2f64.to_radians());
    let turned: Vec<_> = fibres.iter().map(|(d, w)| (turn * *d, *w)).collect();
    let coeffs = vec![fibre_tensor(8, &fibres), fibre_tensor(8, &turned)];
    let centers = vec![DVec3::new(-1.05, 0.0, 0.0), DVec3::new(1.05, 0.0, 0.0)];
    scene(
        vec![glyph_set(symmetric(8), centers, 1.0, coeffs)],
        DVec3::new(0.3, -1.0, 7.5),
    )
}

/// Order 8, two orthogonal populations: the surface pinches to the centre along z, and
/// the camera looks almost straight down that axis.
fn touching_centre() -> Scene {
    let t = fibre_tensor(
        8,
        &[(direction(0.0, 0.0), 1.0), (direction(90.0, 0.0), 1.0)],
    );
    scene(
        vec![glyph_set(symmetric(8), vec![DVec3::ZERO], 1.0, vec![t])],
        DVec3::new(0.2, -0.3, 4.0),
    )
}

/// Order 12, three populations.
fn order_12() -> Scene {
    let t = fibre_tensor(
        12,
        &[
            (direction(0.0, 0.0), 1.0),
            (direction(60.0, 20.0), 0.8),
            (direction(130.0, -30.0), 0.7),
        ],
    );
    scene(
        vec![glyph_set(symmetric(12), vec![DVec3::ZERO], 1.0, vec![t])],
        DVec3::new(1.0, -3.0, 2.5),
    )
}

/// Cubic copper's stiffness tensor C_ijkl (GPa / 168.4), all 81 entries, turned so that
/// its cubic axes are not the world's.
fn stiffness() -> Scene {
    // Divided by C11 so the glyph is O(1).
    let (c11, c12, c44) = (1.0, 121.4 / 168.4, 75.4 / 168.4);
    let voigt = |i: usize, j: usize| match (i, j) {
        (a, b) if a == b => [0, 1, 2][a],
        (0, 1) | (1, 0) => 5,
        (0, 2) | (2, 0) => 4,
        _ => 3,
    };
    let c = |p: usize, q: usize| match (p, q) {
        (p, q) if p == q && p < 3 => c11,
        (p, q) if p < 3 && q < 3 => c12,
        (p, q) if p == q => c44,
        _ => 0.0,
    };
    let rot = DMat3::from_euler(glam::EulerRot::ZYX, 0.4, 0.3, 0.2);
    let mut coeffs = vec![0.0; 81];
    // Rotate: C'_ijkl = R_ia R_jb R_kc R_ld C_abcd.
    for (flat, out) in coeffs.iter_mut().enumerate() {
        let idx = [flat / 27, (flat / 9) % 3, (flat / 3) % 3, flat % 3];
        let mut sum = 0.0;
        for a in 0..81 {
            let s = [a / 27, (a / 9) % 3, (a / 3) % 3, a % 3];
            let r = (0..4).map(|n| rot.col(s[n])[idx[n]]).product::<f64>();
            sum += r * c(voigt(s[0], s[1]), voigt(s[2], s[3]));
        }
        *out = sum;
    }
    let kind = GlyphKind::Tensor(TensorLayout {
        order: 4,
        symmetry: Symmetry::NonSymmetric,
    });
    scene(
        vec![glyph_set(kind, vec![DVec3::ZERO], 1.0, vec![coeffs])],
        DVec3::new(2.0, -3.0, 2.0),
    )
}

/// Order 6, f = (u.x)^6 - 0.9 (u.d2)^6 + 0.7 (u.d3)^6: a negative lobe along d2 that
/// crosses the positive ones, drawn by |f| (`negative: abs`) or left out (`hide`).
fn negative_lobes(negative: NegativeMode) -> Scene {
    let t = fibre_tensor(
        6,
        &[
            (direction(0.0, 0.0), 1.0),
            (direction(90.0, 30.0), -0.9),
            (direction(45.0, -50.0), 0.7),
        ],
    );
    let mut set = glyph_set(symmetric(6), vec![DVec3::ZERO], 1.0, vec![t]);
    set.negative = negative;
    scene(vec![set], DVec3::new(1.5, -3.0, 2.0))
}

/// The median depth error each method is held to, in units of the glyph scale.
fn median_bound(method: Method) -> f64 {
    match method {
        Method::Fixed => 1e-3,
        Method::Exact => 1e-4,
    }
}

/// Renders `scene` with `method` at otherwise default settings and holds it to the
/// reference: no holes, no false hits outside the silhouette band, median error bound.
fn check(name: &str, scene: Scene, method: Method) {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let settings = RenderSettings {
        method,
        ..Default::default()
    };
    let r = common::render_and_compare(&gpu, &mut renderer, &scene, &settings);
    let c = r.comparison;
    let name = format!("{name}_{}", method.name());
    eprintln!("{name}: {c}");
    assert!(
        c.covered > (SIZE * SIZE / 50) as usize,
        "{name}: the glyph covers too little to test: {c}"
    );
    if c.holes != 0 || c.false_hits != 0 || c.median_error >= median_bound(method) {
        common::save_failure_images(&name, &r);
        panic!("{name}: {c}");
    }
}

fn check_default(name: &str, scene: Scene) {
    check(name, scene, Method::Fixed);
}

#[test]
fn thin_crossing_lobes_default_settings() {
    check_default("thin_crossing_lobes", thin_crossing_lobes());
}

#[test]
fn tilted_copy_default_settings() {
    check_default("tilted_copy", tilted_copy());
}

#[test]
fn centre_touching_order_8_default_settings() {
    check_default("touching_centre", touching_centre());
}

#[test]
fn order_12_default_settings() {
    check_default("order_12", order_12());
}

#[test]
fn nonsymmetric_stiffness_default_settings() {
    check_default("stiffness", stiffness());
}

#[test]
fn negative_lobes_shown_default_settings() {
    check_default("negative_shown", negative_lobes(NegativeMode::Abs));
}

#[test]
fn negative_lobes_hidden_default_settings() {
    check_default("negative_hidden", negative_lobes(NegativeMode::Hide));
}

#[test]
fn thin_crossing_lobes_exact() {
    check("thin_crossing_lobes", thin_crossing_lobes(), Method::Exact);
}

#[test]
fn tilted_copy_exact() {
    check("tilted_copy", tilted_copy(), Method::Exact);
}

#[test]
fn centre_touching_order_8_exact() {
    check("touching_centre", touching_centre(), Method::Exact);
}

#[test]
fn order_12_exact() {
    check("order_12", order_12(), Method::Exact);
}

#[test]
fn nonsymmetric_stiffness_exact() {
    check("stiffness", stiffness(), Method::Exact);
}

#[test]
fn negative_lobes_shown_exact() {
    check(
        "negative_shown",
        negative_lobes(NegativeMode::Abs),
        Method::Exact,
    );
}

#[test]
fn negative_lobes_hidden_exact() {
    check(
        "negative_hidden",
        negative_lobes(NegativeMode::Hide),
        Method::Exact,
    );
}

/// The comparison can fail: a coarse step without refinement leaves holes in the thin
/// lobes and centre pinch and large depth errors, and the test sees them.
#[test]
fn coarse_settings_are_detected() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let coarse = RenderSettings {
        step: 0.25,
        refinement: Refinement::None,
        centre_step_factor: 1.0,
        ..Default::default()
    };
    let thin = common::render_and_compare(&gpu, &mut renderer, &thin_crossing_lobes(), &coarse);
    eprintln!("coarse thin lobes: {}", thin.comparison);
    assert!(
        thin.comparison.holes > 0,
        "a 0.25 step must miss parts of the thin lobes: {}",
        thin.comparison
    );
    assert!(thin.comparison.median_error > 1e-3, "{}", thin.comparison);
}

/// Render time of `exact` against `fixed` at its default (step 0.02, secant:4) and at
/// step 0.05 with one interpolation step, on every scene above at 480 x 480 (one ray per
/// pixel). A report, not an assertion: run with `cargo test --test depth_accuracy
/// render_time_report -- --ignored --nocapture`. Each entry is the best wall-clock time
/// of `RUNS` renders after one that creates the pipeline and, on Linux, the mean CPU time
/// of the process per render (the rasteriser's work, which machine load does not inflate
/// the way it does wall-clock time on a busy CPU device). A render includes upload and
/// readback: the `empty` row (one glyph behind the camera) shows that fixed cost.
#[test]
#[ignore = "timing report; run explicitly"]
fn render_time_report() {
    const RUNS: usize = 5;
    const REPORT_SIZE: u32 = 480;
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let configurations = [
        ("fixed 0.02 secant:4", RenderSettings::default()),
        (
            "fixed 0.05 interp",
            RenderSettings {
                step: 0.05,
                refinement: Refinement::Interpolate,
                ..Default::default()
            },
        ),
        (
            "exact",
            RenderSettings {
                method: Method::Exact,
                ..Default::default()
            },
        ),
    ];
    let scenes = [
        ("thin crossing lobes", thin_crossing_lobes()),
        ("tilted copy", tilted_copy()),
        ("centre-touching 8", touching_centre()),
        ("order 12", order_12()),
        ("stiffness", stiffness()),
        ("negative shown", negative_lobes(NegativeMode::Abs)),
        ("negative hidden", negative_lobes(NegativeMode::Hide)),
        ("empty", {
            let mut s = stiffness();
            s.camera.target = DVec3::new(2.0, -6.0, 2.0);
            s
        }),
    ];
    eprintln!(
        "render time (ms, best of {RUNS}) at {REPORT_SIZE}x{REPORT_SIZE} on {}",
        gpu.info
    );
    eprintln!(
        "{:<20}{}",
        "scene: wall | cpu",
        configurations
            .iter()
            .map(|(name, _)| format!("{name:>24}"))
            .collect::<String>()
    );
    let mut totals = vec![(0.0, 0.0); configurations.len()];
    for (name, mut scene) in scenes {
        scene.image = ImageSize {
            width: REPORT_SIZE,
            height: REPORT_SIZE,
        };
        let sets = prepare_scene(&scene, 0.0).expect("prepare");
        let mut row = format!("{name:<20}");
        for (total, (_, settings)) in totals.iter_mut().zip(&configurations) {
            let mut best = f64::INFINITY;
            let mut cpu = 0.0;
            for run in 0..=RUNS {
                let started = Instant::now();
                let cpu_before = process_cpu_ms();
                renderer
                    .render(
                        &gpu,
                        &sets,
                        &scene.camera,
                        REPORT_SIZE,
                        REPORT_SIZE,
                        settings,
                    )
                    .expect("render");
                if run > 0 {
                    best = best.min(started.elapsed().as_secs_f64() * 1e3);
                    cpu += (process_cpu_ms() - cpu_before) / RUNS as f64;
                }
            }
            if name != "empty" {
                total.0 += best;
                total.1 += cpu;
            }
            row += &format!("{best:>14.1} | {cpu:>7.0}");
        }
        eprintln!("{row}");
    }
    eprintln!(
        "{:<20}{}",
        "total (not empty)",
        totals
            .iter()
            .map(|(wall, cpu)| format!("{wall:>14.1} | {cpu:>7.0}"))
            .collect::<String>()
    );
}

/// User + system CPU time of this process (all threads, the rasteriser's included) in
/// ms, from /proc/self/stat (clock ticks of 10 ms); 0 where that file does not exist.
fn process_cpu_ms() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command name in parentheses: utime and stime are the 12th and 13th.
    let fields: Vec<&str> = stat
        .rsplit_once(')')
        .map_or("", |(_, rest)| rest)
        .split_whitespace()
        .collect();
    let ticks = |i: usize| fields.get(i).and_then(|v| v.parse::<f64>().ok());
    match (ticks(11), ticks(12)) {
        (Some(user), Some(system)) => (user + system) * 10.0,
        _ => 0.0,
    }
}
