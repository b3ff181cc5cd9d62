//! SH glyphs on the GPU: real data (DIPY's func_coef) against the float64 reference, and
//! the same glyphs given in another basis or as their tensor (t = M w) render the same.
use crate::common;
use glyphcast::accuracy::compare_depth;
use glyphcast::accuracy::suite::sh_func_coef;
use glyphcast::glyph::sh::{convert_basis, sh_to_tensor};
use glyphcast::glyph::{Symmetry, TensorLayout};
use glyphcast::render::RenderSettings;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::scene::{GlyphKind, Scene, ShBasis};

const SIZE: u32 = 160;

#[test]
fn sh_scene_matches_the_float64_reference() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let r = common::render_and_compare(
        &gpu,
        &mut renderer,
        &sh_func_coef(SIZE),
        &RenderSettings::default(),
    );
    let c = r.comparison;
    eprintln!("sh-func-coef: {c}");
    assert!(c.covered > 1000, "{c}");
    if c.holes != 0 || c.false_hits != 0 || c.median_error >= 1e-3 {
        common::save_failure_images("sh_func_coef", &r);
        panic!("{c}");
    }
}

fn with_set(scene: &Scene, kind: GlyphKind, coeffs: Vec<Vec<f64>>) -> Scene {
    let mut out = scene.clone();
    out.glyph_sets[0].kind = kind;
    out.glyph_sets[0].coeffs = coeffs;
    out
}

#[test]
fn sh_in_another_basis_and_as_a_tensor_render_the_same() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let legacy = sh_func_coef(SIZE);
    let source = legacy.glyph_sets[0].coeffs.clone();
    let from = (ShBasis::Tournier07, true);
    let to = (ShBasis::Descoteaux07, false);
    let descoteaux: Vec<Vec<f64>> = source
        .iter()
        .map(|c| convert_basis(8, from, to, c).expect("conversion"))
        .collect();
    assert!(descoteaux != source, "the conversion changes the numbers");
    let tensor: Vec<Vec<f64>> = source
        .iter()
        .map(|c| sh_to_tensor(8, from.0, from.1, c).expect("t = M w").1)
        .collect();
    let scenes = [
        legacy.clone(),
        with_set(
            &legacy,
            GlyphKind::Sh {
                band: 8,
                basis: to.0,
                legacy: to.1,
            },
            descoteaux,
        ),
        with_set(
            &legacy,
            GlyphKind::Tensor(TensorLayout {
                order: 8,
                symmetry: Symmetry::Symmetric,
            }),
            tensor,
        ),
    ];
    let settings = RenderSettings::default();
    let depths: Vec<Vec<f32>> = scenes
        .iter()
        .map(|s| {
            let sets = prepare_scene(s, 0.0).expect("prepare");
            renderer
                .render_view(
                    &gpu,
                    &sets,
                    &glyphcast::FrameView::new(&s.camera, SIZE, SIZE),
                    &settings,
                )
                .expect("render")
                .distance
        })
        .collect();
    let first: Vec<f64> = depths[0].iter().map(|&d| d as f64).collect();
    for (name, depth) in ["descoteaux07", "tensor"].iter().zip(&depths[1..]) {
        let c = compare_depth(depth, &first, SIZE as usize, SIZE as usize, 0.5);
        eprintln!("{name} vs legacy tournier07: {c}");
        assert!(c.covered > 1000);
        assert_eq!((c.holes, c.false_hits), (0, 0), "{name}: {c}");
        // Only float32 rounding of differently computed coefficients separates them.
        assert!(c.max_error < 1e-4, "{name}: {c}");
    }
}
