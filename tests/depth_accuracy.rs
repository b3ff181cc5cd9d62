//! Rendered depth maps against the float64 reference (exact ray-polynomial roots) on the
//! accuracy suite (`glyphcast::accuracy::suite`): thin crossing lobes, a slightly tilted
//! copy of a glyph (the paper's Fig. 1), a glyph that touches its centre seen down its
//! pinch, order 12, a non-symmetric stiffness tensor, negative lobes shown and hidden,
//! real SH data, plus an order-6 glyph whose negative lobe crosses the positive ones.
//!
//! Every ray-casting method at its default settings: zero holes and zero false hits away
//! from a one-pixel silhouette band, and a median depth error below 1e-3 of the glyph
//! scale for `fixed` (a marcher), below 1e-4 for `interval`, `affine` and `exact` (root
//! finders to float32 precision; they measure ~2e-7). One test per method keeps failures
//! readable. Coarse settings must fail, so the comparison is known to see holes. The
//! exact method's reciprocal variant (r = 1/|f|) is held to the same bar at every even
//! order.
use crate::common;
use glam::DVec3;
use glyphcast::accuracy::suite::{self, SuiteScene};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::NegativeMode;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::{Method, Refinement, RenderSettings};
use glyphcast::scene::{ImageSize, Scene};

const SIZE: u32 = 160;

/// Order 6, f = (u.x)^6 - 0.9 (u.d2)^6 + 0.7 (u.d3)^6: a negative lobe along d2 that
/// crosses the positive ones.
fn crossing_negative_lobe(negative: NegativeMode) -> Scene {
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
    let mut scene = suite::thin_crossing_lobes(SIZE);
    scene.glyph_sets = vec![set];
    scene.camera.eye = DVec3::new(1.5, -3.0, 2.0);
    scene.image = ImageSize {
        width: SIZE,
        height: SIZE,
    };
    scene
}

fn scenes() -> Vec<SuiteScene> {
    let mut scenes = suite::suite(SIZE);
    scenes.push(SuiteScene {
        name: "crossing-negative-abs",
        scene: crossing_negative_lobe(NegativeMode::Abs),
    });
    scenes.push(SuiteScene {
        name: "crossing-negative-hide",
        scene: crossing_negative_lobe(NegativeMode::Hide),
    });
    scenes
}

fn median_bound(method: Method) -> f64 {
    if method.marches() { 1e-3 } else { 1e-4 }
}

fn assert_accurate(name: &str, r: &common::Rendered, median: f64) {
    let c = r.comparison;
    eprintln!("{name}: {c}");
    assert!(
        c.covered > (SIZE * SIZE / 50) as usize,
        "{name}: the glyph covers too little to test: {c}"
    );
    if c.holes != 0 || c.false_hits != 0 || c.median_error >= median {
        common::save_failure_images(name, r);
        panic!("{name}: {c}");
    }
}

fn check_method(method: Method) {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let settings = RenderSettings {
        method,
        ..Default::default()
    };
    for entry in scenes() {
        let r = common::render_and_compare(&gpu, &mut renderer, &entry.scene, &settings);
        assert_accurate(
            &format!("{}-{method}", entry.name),
            &r,
            median_bound(method),
        );
    }
}

#[test]
fn fixed_step_at_its_defaults_on_every_scene() {
    check_method(Method::Fixed);
}

#[test]
fn interval_on_every_scene() {
    check_method(Method::Interval);
}

#[test]
fn affine_on_every_scene() {
    check_method(Method::Affine);
}

#[test]
fn exact_on_every_scene() {
    check_method(Method::Exact);
}

/// The comparison can fail: a coarse step without refinement leaves holes in the thin
/// lobes and centre pinch and large depth errors, and the test sees them.
#[test]
fn coarse_settings_are_detected() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let coarse = RenderSettings {
        method: Method::Fixed,
        step: 0.25,
        refinement: Refinement::None,
        centre_step_factor: 1.0,
        ..Default::default()
    };
    let thin = common::render_and_compare(
        &gpu,
        &mut renderer,
        &suite::thin_crossing_lobes(SIZE),
        &coarse,
    );
    eprintln!("coarse thin lobes: {}", thin.comparison);
    assert!(
        thin.comparison.holes > 0,
        "a 0.25 step must miss parts of the thin lobes: {}",
        thin.comparison
    );
    assert!(thin.comparison.median_error > 1e-3, "{}", thin.comparison);
}

/// The robust methods stay hole-free at a coarse precision (4 pixels): they only stop
/// splitting where the range arithmetic cannot exclude the surface.
#[test]
fn robust_methods_at_coarse_precision_leave_no_holes() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for method in [Method::Interval, Method::Affine] {
        let settings = RenderSettings {
            method,
            precision_px: 4.0,
            ..Default::default()
        };
        for scene in [
            suite::thin_crossing_lobes(SIZE),
            suite::touching_centre(SIZE),
        ] {
            let r = common::render_and_compare(&gpu, &mut renderer, &scene, &settings);
            assert_accurate(&format!("{method}-precision-4"), &r, 1e-3);
        }
    }
}

/// The default settings (the fastest method with no holes on the suite when it was
/// chosen) keep that property on every scene of the accuracy suite.
#[test]
fn default_settings_leave_no_holes_on_the_whole_suite() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for entry in suite::suite(128) {
        let r = common::render_and_compare(
            &gpu,
            &mut renderer,
            &entry.scene,
            &RenderSettings::default(),
        );
        let c = r.comparison;
        eprintln!("{}: {c}", entry.name);
        assert!(c.covered > 300, "{}: {c}", entry.name);
        assert_eq!((c.holes, c.false_hits), (0, 0), "{}: {c}", entry.name);
        assert!(c.median_error < 1e-4, "{}: {c}", entry.name);
    }
}

/// Reciprocal glyphs (scene `shape` `reciprocal`, r = 1/|f|) of every even symmetric
/// order and of a non-symmetric order-4 tensor, from positive forms: 13 fibre directions
/// (cube axes, face and body diagonals) with weights 0.6 to 1.4, so that 1/|f| has
/// lobes between the directions. The exact method's reciprocal shaders against the
/// float64 reference, held to the exact method's bar.
#[test]
fn exact_on_reciprocal_glyphs_of_every_even_order() {
    use glyphcast::glyph::monomials::{
        monomial_index, nonsymmetric_count, nonsymmetric_entry_monomial,
    };
    use glyphcast::glyph::{GlyphShape, Symmetry, TensorLayout};
    use glyphcast::scene::GlyphKind;
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let mut fibres = Vec::new();
    for (k, (a, e)) in [
        (0.0, 0.0),
        (90.0, 0.0),
        (0.0, 90.0),
        (45.0, 0.0),
        (-45.0, 0.0),
        (0.0, 45.0),
        (0.0, -45.0),
        (90.0, 45.0),
        (90.0, -45.0),
        (45.0, 35.26),
        (-45.0, 35.26),
        (45.0, -35.26),
        (-45.0, -35.26),
    ]
    .into_iter()
    .enumerate()
    {
        fibres.push((direction(a, e), 0.6 + 0.8 * ((k * 7) % 13) as f64 / 12.0));
    }
    let settings = RenderSettings {
        method: Method::Exact,
        ..Default::default()
    };
    let mut layouts: Vec<(TensorLayout, Vec<f64>)> = (2..=12)
        .step_by(2)
        .map(|order| {
            (
                TensorLayout {
                    order,
                    symmetry: Symmetry::Symmetric,
                },
                fibre_tensor(order, &fibres),
            )
        })
        .collect();
    let unique = fibre_tensor(4, &fibres);
    let full = (0..nonsymmetric_count(4))
        .map(|flat| unique[monomial_index(4, nonsymmetric_entry_monomial(4, flat))])
        .collect();
    layouts.push((
        TensorLayout {
            order: 4,
            symmetry: Symmetry::NonSymmetric,
        },
        full,
    ));
    for (layout, coeffs) in layouts {
        let mut scene = crossing_negative_lobe(NegativeMode::Abs);
        let mut set = glyph_set(
            GlyphKind::Tensor(layout),
            vec![DVec3::ZERO],
            1.0,
            vec![coeffs],
        );
        set.shape = GlyphShape::Reciprocal;
        scene.glyph_sets = vec![set];
        let r = common::render_and_compare(&gpu, &mut renderer, &scene, &settings);
        let name = format!("reciprocal-{:?}-{}", layout.symmetry, layout.order);
        assert_accurate(&name, &r, median_bound(Method::Exact));
    }
}
