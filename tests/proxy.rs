//! What the fragment path draws around each glyph (`--proxy`): the hull's outline (an
//! octagon on the screen around the glyph's guaranteed 26-sided polytope, at its nearest
//! depth) or the box. Both run the same ray caster on every pixel they cover, so the
//! outline must give the box's image and depth map bit for bit wherever a glyph shows
//! (a pixel it left out would be a hole, one it added cannot hit), on every scene and
//! method, with the near plane cutting glyphs, orthographic and supersampled; and it
//! must launch fewer fragments.
use crate::common::{
    fresh_dir, glyphcast, gpu, render_and_compare, render_and_compare_with, save_failure_images,
    text,
};
use glam::DVec3;
use glyphcast::accuracy::suite;
use glyphcast::bench::workload::{BlockView, block};
use glyphcast::camera::Projection;
use glyphcast::render::glyph_data::{add_pieces, prepare_scene};
use glyphcast::render::{Culling, Method, Proxy, RenderSettings, Shadows};
use glyphcast::scene::Scene;
use glyphcast::{FrameView, Gpu, HeadlessRenderer, RenderedImage};

/// The scene drawn with `settings` and `proxy`.
fn draw(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    scene: &Scene,
    settings: &RenderSettings,
    proxy: Proxy,
) -> RenderedImage {
    let settings = RenderSettings { proxy, ..*settings };
    let sets = prepare_scene(scene, settings.offset as f64).expect("preparing the scene");
    let (w, h) = (scene.image.width, scene.image.height);
    let frame = renderer
        .prepare_view(gpu, &sets, &FrameView::new(&scene.camera, w, h), &settings)
        .expect("preparing the frame");
    renderer.draw(gpu, &frame).expect("drawing");
    renderer.read(gpu, &frame).expect("reading back")
}

/// The outline and the box give the same bits; returns the pixels hit.
fn same_as_the_box(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    name: &str,
    scene: &Scene,
    settings: &RenderSettings,
) -> usize {
    let boxes = draw(gpu, renderer, scene, settings, Proxy::Box);
    let outlines = draw(gpu, renderer, scene, settings, Proxy::Hull);
    let hits = boxes.distance.iter().filter(|d| !d.is_nan()).count();
    assert!(hits > 100, "{name}: only {hits} pixels hit");
    let differing = crate::common::differing_distances(&boxes, &outlines);
    assert_eq!(
        differing, 0,
        "{name}: {differing} depth values differ between the hull's outline and the box"
    );
    assert!(
        boxes.rgba == outlines.rgba,
        "{name}: the image differs between the hull's outline and the box"
    );
    hits
}

#[test]
fn the_hull_gives_the_box_image_on_the_accuracy_suite_and_every_method() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    assert_eq!(RenderSettings::default().proxy, Proxy::Box, "the default");
    for entry in suite::suite(160) {
        let settings = RenderSettings::default();
        same_as_the_box(&gpu, &mut renderer, entry.name, &entry.scene, &settings);
    }
    // Every ray-casting method reads the same vertex shader; the robust ones on the
    // first scenes only (they are slow on lavapipe).
    let scenes = suite::suite(96);
    for method in [
        Method::Fixed,
        Method::Interval,
        Method::Affine,
        Method::Impostor,
    ] {
        for entry in scenes.iter().take(3) {
            let settings = RenderSettings {
                method,
                ..RenderSettings::default()
            };
            let name = format!("{} with {method:?}", entry.name);
            same_as_the_box(&gpu, &mut renderer, &name, &entry.scene, &settings);
        }
    }
    // An offset grows each glyph: its polytope grows with it.
    let entry = &scenes[0];
    let settings = RenderSettings {
        method: Method::Affine,
        offset: 0.3,
        ..RenderSettings::default()
    };
    same_as_the_box(&gpu, &mut renderer, "offset 0.3", &entry.scene, &settings);
}

/// Blocks of band-8 fODFs seen head-on, from a corner, orthographically, from inside
/// (the near plane cuts the glyphs around the eye) and with the near plane through some
/// lobes, then culled in passes, by early outs and not at all, with hard shadows and 4
/// samples: the cases both proxies are held to.
fn block_cases() -> Vec<(&'static str, Scene, RenderSettings)> {
    let front = block((8, 8, 12), 8, BlockView::Front, 160, 120).expect("block workload");
    let corner = block((6, 6, 6), 8, BlockView::Corner, 160, 120).expect("block workload");
    let mut orthographic = front.clone();
    orthographic.camera.projection = Projection::Orthographic { height: 10.0 };
    let mut inside = front.clone();
    inside.camera.eye = DVec3::new(0.3, 0.2, -2.5);
    inside.camera.target = DVec3::new(0.3, 0.2, -20.0);
    // Close to a glyph's lobes, the near plane through some of them.
    let mut grazing = front.clone();
    grazing.camera.eye = DVec3::new(0.45, 0.1, 0.9);
    grazing.camera.target = DVec3::new(-2.0, -1.0, -8.0);
    let base = RenderSettings::default();
    let culled = |cull| RenderSettings { cull, ..base };
    vec![
        ("head-on", front.clone(), base),
        ("from a corner", corner.clone(), base),
        ("orthographic", orthographic, base),
        ("the camera inside", inside, base),
        ("the near plane through lobes", grazing, base),
        ("without culling", front.clone(), culled(Culling::Off)),
        ("passes", front, culled(Culling::Passes)),
        ("early outs", corner.clone(), culled(Culling::EarlyOut)),
        (
            "hard shadows",
            corner.clone(),
            RenderSettings {
                shadows: Shadows::Hard,
                ..base
            },
        ),
        ("4 samples", corner, RenderSettings { samples: 4, ..base }),
    ]
}

/// Blocks seen head-on, from a corner, orthographically and from inside (the near plane
/// cuts the glyphs around the eye: their outline is that of the box's part in front of
/// it), culled and not, with shadows and supersampling; and the float64 reference finds
/// no hole and no false hit with the outline.
#[test]
fn the_hull_gives_the_box_image_on_blocks_from_every_side() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let cases = block_cases();
    for (name, scene, settings) in &cases {
        let name = format!("block, {name}");
        same_as_the_box(&gpu, &mut renderer, &name, scene, settings);
    }
    let base = RenderSettings::default();
    let inside = &cases[3].1;
    let grazing = &cases[4].1;
    for (name, scene) in [("inside", inside), ("grazing", grazing)] {
        let r = render_and_compare(&gpu, &mut renderer, scene, &base);
        if r.comparison.holes + r.comparison.false_hits > 0 {
            save_failure_images(&format!("proxy-block-{name}"), &r);
        }
        assert_eq!(r.comparison.holes, 0, "{name}: holes against float64");
        assert_eq!(r.comparison.false_hits, 0, "{name}: false hits");
    }
}

/// `glyphcast bench`'s work counters of one frame of `workload` with `--proxy`:
/// fragments and evaluations per covered pixel.
fn work(dir: &std::path::Path, workload: &str, proxy: &str) -> (f64, f64) {
    let out = glyphcast(&[
        "bench",
        "--workload",
        workload,
        "--proxy",
        proxy,
        "--width",
        "480",
        "--height",
        "270",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--out",
        text(dir),
    ]);
    assert!(
        out.status.success(),
        "{workload}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = std::fs::read_to_string(dir.join("results.json")).expect("results.json");
    let json: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    let r = &json["results"][0];
    let covered = r["covered_pixels"].as_f64().expect("covered pixels");
    assert!(covered > 1000.0, "{workload}: {covered} covered pixels");
    let count = |k: &str| {
        r["work"][k]
            .as_f64()
            .unwrap_or_else(|| panic!("work.{k}: {r}"))
    };
    (count("fragments") / covered, count("evaluations") / covered)
}

/// What the outline saves, counted: on fields of band-8 fODFs it launches at least 5 %
/// fewer fragments and makes at least 10 % fewer root isolations per covered pixel than
/// the box (8 and 16 % on the 256-glyph field at 1280x720; 18 and 22 % with 10,000).
#[test]
fn the_hull_launches_fewer_fragments_than_the_box() {
    let dir = fresh_dir("proxy-work");
    for workload in ["fodf:256:8", "fodf:2500:8"] {
        let (box_fragments, box_evaluations) = work(&dir, workload, "box");
        let (fragments, evaluations) = work(&dir, workload, "hull");
        assert!(
            fragments <= 0.95 * box_fragments,
            "{workload}: {fragments:.2} fragments per covered pixel, the box {box_fragments:.2}"
        );
        assert!(
            evaluations <= 0.9 * box_evaluations,
            "{workload}: {evaluations:.2} evaluations per covered pixel, the box \
             {box_evaluations:.2}"
        );
    }
}

/// The scene drawn with the pieces (`--proxy pieces`) against the float64 reference:
/// with each glyph's own pieces (`own`, [`add_pieces`]) or with the octants of its
/// 26-sided polytope (what a host that skips [`add_pieces`] gets). No hole and no false
/// hit, depth within the ray casters' tolerance, and the box's coverage pixel for pixel
/// outside the reference's silhouette band. Returns the pixels covered.
fn pieces_match_the_reference(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    name: &str,
    scene: &Scene,
    settings: &RenderSettings,
    own: bool,
) -> usize {
    let pieces = RenderSettings {
        proxy: Proxy::Pieces,
        ..*settings
    };
    let r = render_and_compare_with(gpu, renderer, scene, &pieces, |sets| {
        if own {
            add_pieces(sets).expect("bounding the pieces");
            for set in sets.iter() {
                assert_eq!(
                    set.pieces.len(),
                    set.len(),
                    "{name}: every glyph has pieces"
                );
            }
        }
    });
    if r.comparison.holes + r.comparison.false_hits > 0 {
        save_failure_images(&format!("pieces-{name}"), &r);
    }
    let c = &r.comparison;
    assert_eq!(
        c.holes, 0,
        "{name}: holes against float64 with the pieces: {c}"
    );
    assert_eq!(c.false_hits, 0, "{name}: false hits with the pieces: {c}");
    let boxes = render_and_compare(gpu, renderer, scene, settings);
    let b = &boxes.comparison;
    // The largest error within the ray casters' tolerance (1e-4 of the glyph: a grazing
    // ray's nearly double root is isolated in another interval than the box's), the
    // 99th percentile as the box's.
    assert!(
        c.max_error <= (2.0 * b.max_error).max(1e-4 * r.scale)
            && c.p99_error <= (2.0 * b.p99_error).max(1e-6 * r.scale),
        "{name}: depth errors with the pieces {c}, with the box {b}"
    );
    let band = glyphcast::accuracy::silhouette_band(
        &r.reference,
        scene.image.width as usize,
        scene.image.height as usize,
    );
    let coverage = |d: &f32| !d.is_nan();
    let differing = (r.image.distance.iter().zip(&boxes.image.distance))
        .zip(&band)
        .filter(|((p, b), band)| !**band && coverage(p) != coverage(b))
        .count();
    assert_eq!(
        differing, 0,
        "{name}: pixels covered by one of pieces and box only"
    );
    c.covered
}

/// The pieces on the accuracy suite (its fODFs, thin lobes, near-zero, negative lobes
/// hidden and shown, non-symmetric tensors), by their own bounds and by the polytope's
/// octants, and on the blocks of [`block_cases`] by their own.
#[test]
fn the_pieces_find_every_reference_hit() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let base = RenderSettings::default();
    for entry in suite::suite(160) {
        for own in [true, false] {
            let name = format!("{} (own pieces {own})", entry.name);
            pieces_match_the_reference(&gpu, &mut renderer, &name, &entry.scene, &base, own);
        }
    }
    for (name, scene, settings) in block_cases() {
        let name = format!("block, {name}");
        pieces_match_the_reference(&gpu, &mut renderer, &name, &scene, &settings, true);
    }
}

/// Rays along the pieces' seams: orthographic views of odd size along each axis of a
/// glyph's pieces' frame (read from its GPU words), rolled both ways, so that the middle
/// row and column of pixels run inside the cone planes that neighbouring pieces share,
/// and the middle pixel along their common axis; and views across the largest lobe (the
/// frame's corner diagonal) at its tip. No pinhole, no false hit, the box's coverage.
#[test]
fn rays_along_the_seams_and_at_the_tips_find_the_surface() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for entry in suite::suite(161).into_iter().take(4) {
        let mut sets = prepare_scene(&entry.scene, 0.0).expect("preparing the scene");
        add_pieces(&mut sets).expect("bounding the pieces");
        let (Some(set), Some(glyph)) = (sets.first(), entry.scene.glyph_sets.first()) else {
            continue;
        };
        let Some(words) = set.pieces.first() else {
            continue;
        };
        let q = glam::Quat::from_xyzw(
            f32::from_bits(words[0]),
            f32::from_bits(words[1]),
            f32::from_bits(words[2]),
            f32::from_bits(words[3]),
        )
        .as_dquat()
        .normalize();
        let axes = [DVec3::X, DVec3::Y, DVec3::Z].map(|a| q * a);
        let centre = glyph.centers[0];
        let radius = f64::from(set.instances[0][3]);
        let mut views = Vec::new();
        for k in 0..3 {
            for roll in [1, 2] {
                views.push((axes[k], axes[(k + roll) % 3]));
            }
        }
        let lobe = (axes[0] + axes[1] + axes[2]).normalize();
        views.push((axes[0].cross(lobe).normalize(), lobe));
        views.push((axes[1].cross(lobe).normalize(), lobe));
        for (i, (forward, up)) in views.into_iter().enumerate() {
            let mut scene = entry.scene.clone();
            scene.glyph_sets.truncate(1);
            let set = &mut scene.glyph_sets[0];
            set.centers.truncate(1);
            set.scales.truncate(1);
            set.coeffs.truncate(1);
            scene.image.width = 161;
            scene.image.height = 121;
            scene.camera.eye = centre - 4.0 * radius * forward;
            scene.camera.target = centre;
            scene.camera.up = up;
            scene.camera.projection = Projection::Orthographic {
                height: 2.6 * radius,
            };
            let name = format!("{} seam view {i}", entry.name);
            let base = RenderSettings::default();
            pieces_match_the_reference(&gpu, &mut renderer, &name, &scene, &base, true);
        }
    }
}

/// What the pieces save, counted: on the 256-glyph field of band-8 fODFs at least 25 %
/// fewer root isolations and 10 % fewer fragments per covered pixel than the box (31 and
/// 19 % at 1280x720).
#[test]
fn the_pieces_isolate_fewer_roots_than_the_box() {
    let dir = fresh_dir("proxy-pieces-work");
    let workload = "fodf:256:8";
    let (box_fragments, box_evaluations) = work(&dir, workload, "box");
    let (fragments, evaluations) = work(&dir, workload, "pieces");
    assert!(
        fragments <= 0.9 * box_fragments,
        "{fragments:.2} fragments per covered pixel, the box {box_fragments:.2}"
    );
    assert!(
        evaluations <= 0.75 * box_evaluations,
        "{evaluations:.2} evaluations per covered pixel, the box {box_evaluations:.2}"
    );
}
