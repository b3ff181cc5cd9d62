//! A one-shot render draws small symmetric sets of lower orders with the pipeline of the
//! highest order of their parity (`render::promote`): one `exact` pipeline for the demo
//! instead of three. The picture must be the one the per-order pipelines draw, and both
//! must agree with the float64 reference.
use crate::common;

use glyphcast::accuracy::compare_depth;
use glyphcast::demo::demo_scene;
use glyphcast::glyph::reference::reference_depth;
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::render::RenderSettings;
use glyphcast::render::glyph_data::{GlyphSetData, prepare_scene};
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::options::prepare_render;
use glyphcast::render::promote::{PROMOTABLE_GLYPHS, early_variants, promote_small_sets};
use glyphcast::render::{Method, RenderPath, ShapeShader};
use glyphcast::scene::Scene;

fn orders(sets: &[GlyphSetData]) -> Vec<u32> {
    sets.iter().map(|s| s.layout.order).collect()
}

fn symmetric(order: u32) -> TensorLayout {
    TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    }
}

#[test]
fn the_demo_draws_with_one_pipeline_and_the_same_picture() {
    let scene = demo_scene();
    let settings = RenderSettings::default();
    let (w, h) = (scene.image.width, scene.image.height);
    let own = prepare_scene(&scene, 0.0).expect("preparing");
    assert_eq!(orders(&own), [4, 6, 8, 8]);
    let promoted = prepare_render(scene.clone(), settings, None).expect("preparing");
    assert_eq!(
        orders(&promoted.sets),
        [8, 8, 8, 8],
        "orders 4 and 6 raised to 8"
    );
    // Only order 8's pipeline is compiled before the preparation; 4 and 6 may be raised.
    assert_eq!(
        early_variants(&scene, &settings),
        [(symmetric(8), Method::Exact, ShapeShader::Polynomial)]
    );

    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let view = glyphcast::FrameView::new(&scene.camera, w, h);
    let a = renderer
        .render_view(&gpu, &own, &view, &settings)
        .expect("rendering with a pipeline per order");
    let b = renderer
        .render_view(&gpu, &promoted.sets, &view, &settings)
        .expect("rendering with order 8's pipeline");
    let hits = |d: &[f32]| d.iter().filter(|v| !v.is_nan()).count();
    assert!(hits(&a.distance) > 50_000, "{}", hits(&a.distance));
    let mut coverage_differs = 0;
    let mut largest = 0.0f32;
    for (x, y) in a.distance.iter().zip(&b.distance) {
        match (x.is_nan(), y.is_nan()) {
            (false, false) => largest = largest.max((x - y).abs() / x.abs()),
            (true, true) => {}
            _ => coverage_differs += 1,
        }
    }
    // Measured: 0 pixels and 4.4e-7 (float32 rounding of the raised coefficients).
    assert!(
        coverage_differs <= 3,
        "{coverage_differs} pixels hit by one only"
    );
    assert!(largest < 2e-5, "relative depth difference {largest}");
    let colour_differs = a
        .rgba
        .chunks(4)
        .zip(b.rgba.chunks(4))
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(u, v)| u.abs_diff(*v) > 2))
        .count();
    assert!(
        colour_differs <= 20,
        "{colour_differs} pixels differ in colour"
    );

    // Both against the float64 reference of the scene's own glyphs.
    let world: Vec<_> = own.iter().flat_map(|s| s.world.iter().cloned()).collect();
    let reference = reference_depth(&world, &scene.camera, w, h);
    let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
    for image in [&a, &b] {
        let c = compare_depth(&image.distance, &reference, w as usize, h as usize, scale);
        assert_eq!((c.holes, c.false_hits), (0, 0), "{c}");
        assert!(c.median_error < 1e-4, "{c}");
    }
    gpu.check_validation().expect("no validation errors");
}

/// The demo's sets, each repeated `copies` times along x (a larger set of the same
/// glyphs).
fn widened(scene: &Scene, copies: usize) -> Scene {
    let mut scene = scene.clone();
    for set in &mut scene.glyph_sets {
        let n = set.centers.len();
        for copy in 1..copies {
            for i in 0..n {
                let mut c = set.centers[i];
                c.x += 7.0 * copy as f64;
                set.centers.push(c);
                set.scales.push(set.scales[i]);
                set.coeffs.push(set.coeffs[i].clone());
            }
        }
    }
    scene
}

#[test]
fn only_small_sets_of_the_default_method_are_raised() {
    let scene = demo_scene();
    let settings = RenderSettings::default();
    let (w, h) = (scene.image.width, scene.image.height);
    let prepare = |scene: &Scene, settings: &RenderSettings| {
        let mut sets = prepare_scene(scene, 0.0).expect("preparing");
        let raised = promote_small_sets(&mut sets, &scene.camera, w, h, settings);
        (orders(&sets), raised)
    };
    assert_eq!(prepare(&scene, &settings), (vec![8, 8, 8, 8], 2));

    // Other methods and the compute path draw every order with its own shader.
    for method in [Method::Affine, Method::Impostor] {
        let other = RenderSettings { method, ..settings };
        assert_eq!(prepare(&scene, &other), (vec![4, 6, 8, 8], 0), "{method}");
    }
    let compute = RenderSettings {
        path: RenderPath::Compute,
        ..settings
    };
    assert_eq!(prepare(&scene, &compute), (vec![4, 6, 8, 8], 0));

    // Supersampled 16 times, or seen from close up, the glyphs cover too many pixels to
    // be drawn by order 8.
    let supersampled = RenderSettings {
        samples: 16,
        ..settings
    };
    assert_eq!(prepare(&scene, &supersampled), (vec![4, 6, 8, 8], 0));
    let mut close = scene.clone();
    close.camera.eye = close.camera.target + 0.25 * (close.camera.eye - close.camera.target);
    assert_eq!(prepare(&close, &settings), (vec![4, 6, 8, 8], 0));

    // A set past PROMOTABLE_GLYPHS keeps its pipeline, and so does every set of its
    // layout (raising the others would save nothing); it is compiled early.
    let mut mixed = scene.clone();
    let big = widened(&scene, PROMOTABLE_GLYPHS / 6 + 1).glyph_sets[0].clone();
    mixed.glyph_sets.push(big);
    let early = early_variants(&mixed, &settings);
    let exact = |order| (symmetric(order), Method::Exact, ShapeShader::Polynomial);
    assert!(early.contains(&exact(4)), "{early:?}");
    assert!(!early.contains(&exact(6)), "{early:?}");
    assert_eq!(prepare(&mixed, &settings), (vec![4, 8, 8, 8, 4], 1));
}
