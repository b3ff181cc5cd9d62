//! Hidden glyphs skipped (`--cull`, glyphcast::render::visibility): the glyphs are drawn
//! front to back, in passes that each skip the fragments behind the depth the earlier
//! passes wrote, or in one pass whose fragments behind a hit found before skip the root
//! isolation (early outs). Culling must never change a pixel: every scene here gives the
//! same depth map and image, bit for bit, with culling off and each way on, and agrees
//! with the float64 reference; the scenes that need several passes are checked to be
//! culled.
use crate::common::{fresh_dir, glyphcast, gpu, render_and_compare, save_failure_images, text};
use glam::DVec3;
use glyphcast::accuracy::suite;
use glyphcast::bench::workload::{BlockView, block};
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::{AmbientOcclusion, Culling, Method, RenderSettings, Shadows};
use glyphcast::scene::{ImageSize, Scene};
use glyphcast::{FrameView, Gpu, HeadlessRenderer, RenderedImage};

/// The scene drawn with `settings` and `cull`: its image and the passes its glyphs took
/// (and how they were culled: `image.culling`).
fn draw(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    scene: &Scene,
    (settings, cull): (&RenderSettings, Culling),
) -> (RenderedImage, usize) {
    let settings = RenderSettings { cull, ..*settings };
    let sets = prepare_scene(scene, 0.0).expect("preparing the scene");
    let (w, h) = (scene.image.width, scene.image.height);
    let frame = renderer
        .prepare_view(gpu, &sets, &FrameView::new(&scene.camera, w, h), &settings)
        .expect("preparing the frame");
    renderer.draw(gpu, &frame).expect("drawing");
    let image = renderer.read(gpu, &frame).expect("reading back");
    assert_eq!(
        (image.passes, image.culling),
        (frame.passes(), frame.culling()),
        "the image says how it was drawn"
    );
    (image, frame.passes())
}

/// Culling on (each way: the device's choice, passes, early outs) and off give the same
/// bits; returns the passes with `Culling::Passes`.
fn same_with_and_without(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    name: &str,
    scene: &Scene,
) -> usize {
    let settings = RenderSettings::default();
    same_with_and_without_settings(gpu, renderer, name, scene, &settings)
}

/// [`same_with_and_without`] with `settings` (their `cull` set both ways).
fn same_with_and_without_settings(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    name: &str,
    scene: &Scene,
    settings: &RenderSettings,
) -> usize {
    let (off, off_passes) = draw(gpu, renderer, scene, (settings, Culling::Off));
    assert_eq!(off_passes, 1, "{name}: without culling, one pass");
    assert_eq!(off.culling, Culling::Off, "{name}: without culling");
    let hits = off.distance.iter().filter(|d| !d.is_nan()).count();
    assert!(hits > 100, "{name}: only {hits} pixels hit");
    let mut in_passes = 0;
    for cull in [Culling::Passes, Culling::EarlyOut, Culling::Occluded] {
        let (on, passes) = draw(gpu, renderer, scene, (settings, cull));
        assert_eq!(off.distance.len(), on.distance.len(), "{name}: image sizes");
        let how = format!("--cull {cull}: {passes} passes, {}", on.culling);
        let differing = crate::common::differing_distances(&off, &on);
        assert_eq!(
            differing, 0,
            "{name}: {differing} depth values differ with culling ({how})"
        );
        assert!(
            on.rgba == off.rgba,
            "{name}: the image differs with culling ({how})"
        );
        // A frame whose glyphs overlap (the passes asked for by name cut it) is culled
        // each way it is asked to be by name (the exact method's shader has the early
        // outs, taken wherever the glyphs make more than one cluster); `occluded` decides
        // by the device and the frame's layers (render::visibility), which the tests of
        // the blocks and of DIPY's block below check.
        if cull == Culling::Passes {
            in_passes = passes;
        }
        let exact = settings.method == Method::Exact;
        let expected = match cull {
            Culling::Passes if passes > 1 => &[Culling::Passes][..],
            Culling::Passes => &[Culling::Off, Culling::Passes],
            Culling::EarlyOut if exact && in_passes > 1 => &[Culling::EarlyOut],
            Culling::EarlyOut if exact => &[Culling::EarlyOut, Culling::Off],
            Culling::EarlyOut => &[Culling::Off],
            _ => &[Culling::Passes, Culling::EarlyOut, Culling::Off],
        };
        assert!(expected.contains(&on.culling), "{name}: {how}");
        if on.culling != Culling::Passes {
            assert_eq!(passes, 1, "{name}: {how}");
        }
    }
    in_passes
}

#[test]
fn culling_changes_no_pixel_of_the_accuracy_suite_or_of_blocks() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for entry in suite::suite(160) {
        same_with_and_without(&gpu, &mut renderer, entry.name, &entry.scene);
    }
    // Glyphs that fill their voxels (half the workload's size), and the workload's, whose
    // lobes cross into the next layers' (a later pass's glyph then shows in front of an
    // earlier one's).
    for (view, grow) in [
        (BlockView::Front, 0.5),
        (BlockView::Corner, 0.5),
        (BlockView::Front, 1.0),
        (BlockView::Corner, 1.0),
    ] {
        let mut scene = block((8, 8, 12), 8, view, 240, 180).expect("block workload");
        for scale in &mut scene.glyph_sets[0].scales {
            *scale *= grow;
        }
        let name = format!("block 8x8x12 ({view:?}, glyphs x{grow})");
        let passes = same_with_and_without(&gpu, &mut renderer, &name, &scene);
        // (A corner view of thin glyphs, depth complexity about 3, is one pass.)
        if grow == 1.0 || view == BlockView::Front {
            assert!(
                passes >= 2,
                "{name}: drawn in {passes} passes, so nothing was culled"
            );
        }
        let settings = RenderSettings {
            cull: Culling::Occluded,
            ..RenderSettings::default()
        };
        let r = render_and_compare(&gpu, &mut renderer, &scene, &settings);
        if r.comparison.holes + r.comparison.false_hits > 0 {
            save_failure_images(&format!("visibility-block-{view:?}-{grow}"), &r);
        }
        assert_eq!(
            r.comparison.holes, 0,
            "{name}: holes against the float64 reference"
        );
        assert_eq!(r.comparison.false_hits, 0, "{name}: false hits");
    }
}

/// Culling is the default, so it must leave every feature of a frame as it was: shadows
/// (cast after the frame from its hits), ambient occlusion, supersampling (drawn at twice
/// the size), an orthographic camera and a camera inside the block (boxes cut by the near
/// plane), each on a block drawn in several passes.
#[test]
fn culling_keeps_every_pixel_with_shadows_occlusion_supersampling_and_orthographic_views() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    assert_eq!(
        RenderSettings::default().cull,
        Culling::Occluded,
        "the default"
    );
    let scene = block((8, 8, 12), 8, BlockView::Front, 160, 120).expect("block workload");
    let mut orthographic = scene.clone();
    orthographic.camera.projection = Projection::Orthographic { height: 10.0 };
    // The eye between the block's layers (at z = 0, -1, ...), off the glyphs' centres:
    // the near plane cuts the boxes of the glyphs around it, in the first pass and later.
    let mut inside = scene.clone();
    inside.camera.eye = DVec3::new(0.3, 0.2, -2.5);
    inside.camera.target = DVec3::new(0.3, 0.2, -20.0);
    let base = RenderSettings::default();
    let cases = [
        (
            "hard shadows",
            &scene,
            RenderSettings {
                shadows: Shadows::Hard,
                ..base
            },
        ),
        (
            "soft shadows and ambient occlusion",
            &scene,
            RenderSettings {
                shadows: Shadows::Soft { radius_deg: 4.0 },
                ambient_occlusion: AmbientOcclusion::On { reach: 1.0 },
                ..base
            },
        ),
        ("4 samples", &scene, RenderSettings { samples: 4, ..base }),
        ("orthographic", &orthographic, base),
        ("the camera inside", &inside, base),
    ];
    for (name, scene, settings) in cases {
        let name = format!("block 8x8x12, {name}");
        let passes = same_with_and_without_settings(&gpu, &mut renderer, &name, scene, &settings);
        assert!(
            passes >= 2,
            "{name}: drawn in {passes} passes, so nothing was culled"
        );
    }
}

/// `render` says when it culled: a block saved by `bench` is culled by default (in
/// several passes, or by early outs), and drawn in one pass with `--cull off`, to the
/// same depth map.
#[test]
fn render_culls_by_default_and_says_so() {
    let dir = fresh_dir("visibility-render");
    let scene = dir.join("block.json");
    let bench = glyphcast(&[
        "bench",
        "--workload",
        "block:8:8:12:8",
        "--width",
        "160",
        "--height",
        "120",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--save-scene",
        text(&scene),
        "--out",
        text(&dir),
    ]);
    assert!(
        bench.status.success(),
        "{}",
        String::from_utf8_lossy(&bench.stderr)
    );
    let mut depths = Vec::new();
    for cull in [None, Some("off")] {
        let (png, npy) = (dir.join("block.png"), dir.join("block.npy"));
        let _ = std::fs::remove_file(&png);
        let _ = std::fs::remove_file(&npy);
        let mut args = vec![
            "render",
            text(&scene),
            "-o",
            text(&png),
            "--depth-out",
            text(&npy),
        ];
        args.extend(cull.map(|c| ["--cull", c]).into_iter().flatten());
        let run = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{stderr}");
        let line = stderr
            .lines()
            .find(|l| l.starts_with("rendered "))
            .unwrap_or_else(|| panic!("no summary line: {stderr}"));
        // "... on the fragment path (auto) in 9 passes (hidden glyphs culled): ..."
        let culled = line
            .split_once(" passes (hidden glyphs culled)")
            .and_then(|(before, _)| before.rsplit(' ').next())
            .and_then(|n| n.parse::<usize>().ok());
        // (Or, on a device that jumps over code no pixel runs: "... in one pass front to
        // back (hidden glyphs culled by early outs): ...".)
        let early_outs =
            line.contains(" in one pass front to back (hidden glyphs culled by early outs)");
        match cull {
            None => assert!(
                culled.is_some_and(|n| n >= 2) || early_outs,
                "by default the block is culled: {line}"
            ),
            Some(_) => assert!(!line.contains("culled"), "--cull off: one pass: {line}"),
        }
        depths.push(std::fs::read(&npy).expect("the depth map"));
    }
    assert!(depths[0] == depths[1], "the depth maps differ with culling");
}

/// A wall of six layers of touching spheres, seen from straight above, and behind it a
/// glyph whose thin lobe points up into the gap between four spheres (the gaps of the
/// layers line up): the wall's first layers are drawn in the first pass and the glyph in
/// a later one, where all of it but the lobe's tip is hidden. Culling must keep the tip
/// (a few pixels).
fn peeking_lobe() -> Scene {
    let sphere = vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0];
    let mut centers = Vec::new();
    for layer in [0.0, -2.0, -4.0, -6.0, -8.0, -10.0] {
        for j in 0..8 {
            for i in 0..8 {
                centers.push(DVec3::new(2.0 * i as f64, 2.0 * j as f64, layer));
            }
        }
    }
    let wall = glyph_set(
        symmetric(2),
        centers.clone(),
        1.0,
        vec![sphere; centers.len()],
    );
    let lobe = fibre_tensor(8, &[(direction(0.0, 90.0), 1.0)]);
    let behind = glyph_set(
        symmetric(8),
        vec![DVec3::new(7.0, 7.0, -13.0)],
        1.5,
        vec![lobe],
    );
    Scene {
        glyph_sets: vec![wall, behind],
        camera: Camera {
            projection: Projection::Orthographic { height: 20.0 },
            eye: DVec3::new(7.0, 7.0, 10.0),
            target: DVec3::new(7.0, 7.0, 0.0),
            up: DVec3::Y,
        },
        image: ImageSize {
            width: 240,
            height: 240,
        },
    }
}

#[test]
fn a_thin_lobe_peeking_through_a_gap_is_kept() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let scene = peeking_lobe();
    let passes = same_with_and_without(&gpu, &mut renderer, "peeking lobe", &scene);
    assert!(
        passes >= 2,
        "the lobe's glyph must come in a later pass ({passes} passes)"
    );
    let settings = RenderSettings {
        cull: Culling::Occluded,
        ..RenderSettings::default()
    };
    let r = render_and_compare(&gpu, &mut renderer, &scene, &settings);
    if r.comparison.holes + r.comparison.false_hits > 0 {
        save_failure_images("visibility-peeking-lobe", &r);
    }
    assert_eq!(r.comparison.holes, 0, "holes against the float64 reference");
    assert_eq!(r.comparison.false_hits, 0, "false hits");
    // The lobe's tip: hits beyond the wall's bottom (z = -11, ray distance 21 from the
    // eye at z = 10), only through the gap.
    let tip = r.image.distance.iter().filter(|d| **d > 21.0).count();
    let reference_tip = r.reference.iter().filter(|d| **d > 21.0).count();
    assert!(tip >= 4, "the lobe's tip shows in {tip} pixels");
    assert!(
        tip.abs_diff(reference_tip) <= reference_tip / 5 + 2,
        "the tip: {tip} pixels, the reference {reference_tip}"
    );
}

/// Culling keeps a known depth per pixel in one storage buffer: a target whose known
/// depths exceed the device's maxStorageBufferRange (8192 x 8192 on lavapipe of Mesa 25,
/// 128 MiB) is drawn without culling, with no validation message and the same bits. The
/// pass's storage-buffer cap stands in for the device's range here.
#[test]
fn a_target_too_large_for_its_known_depths_is_drawn_without_culling() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let scene = block((8, 8, 12), 8, BlockView::Front, 240, 180).expect("block workload");
    let (culled, passes) = draw(
        &gpu,
        &mut renderer,
        &scene,
        (&RenderSettings::default(), Culling::Passes),
    );
    assert!(passes >= 2, "the block needs passes ({passes})");
    assert_eq!(culled.culling, Culling::Passes);
    // The known depths take 16 + 4 bytes a pixel; the glyphs' batches fit (split).
    let pixels = 240 * 180;
    renderer
        .pass_mut()
        .set_storage_buffer_limit(Some(4 * pixels));
    let (off, _) = draw(
        &gpu,
        &mut renderer,
        &scene,
        (&RenderSettings::default(), Culling::Off),
    );
    for cull in [Culling::Passes, Culling::EarlyOut, Culling::Occluded] {
        let (capped, passes) = draw(
            &gpu,
            &mut renderer,
            &scene,
            (&RenderSettings::default(), cull),
        );
        assert_eq!(
            (capped.culling, passes),
            (Culling::Off, 1),
            "--cull {cull} under the cap"
        );
        assert_eq!(
            crate::common::differing_distances(&off, &capped),
            0,
            "--cull {cull}"
        );
        assert!(capped.rgba == off.rgba, "--cull {cull}: the image differs");
        assert_eq!(
            crate::common::differing_distances(&culled, &capped),
            0,
            "--cull {cull}"
        );
        assert!(
            capped.rgba == culled.rgba,
            "--cull {cull}: differs from the culled image"
        );
    }
    renderer.pass_mut().set_storage_buffer_limit(None);
}

/// The result of one `glyphcast bench` frame (no warm-up) of `input` (a workload or a
/// scene file) with `cull` at `size` (width, height), from its results.json.
fn bench_result(
    dir: &std::path::Path,
    input: &[&str],
    cull: &str,
    (width, height): (&str, &str),
) -> serde_json::Value {
    let mut args = vec!["bench"];
    args.extend(input);
    args.extend([
        "--cull", cull, "--width", width, "--height", height, "--frames", "1", "--warmup", "0",
        "--out",
    ]);
    args.push(text(dir));
    let out = glyphcast(&args);
    assert!(
        out.status.success(),
        "{input:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = std::fs::read_to_string(dir.join("results.json")).expect("results.json");
    let json: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    json["results"][0].clone()
}

/// `glyphcast bench`'s work counters of one frame of `workload` (320x180) with `cull`:
/// fragments and evaluations per covered pixel, and the passes.
fn work_per_pixel(dir: &std::path::Path, workload: &str, cull: &str) -> (f64, f64, u64) {
    let r = bench_result(dir, &["--workload", workload], cull, ("320", "180"));
    let covered = r["covered_pixels"].as_f64().expect("covered pixels");
    assert!(covered > 1000.0, "{workload}: {covered} covered pixels");
    let work = |k: &str| {
        r["work"][k]
            .as_f64()
            .unwrap_or_else(|| panic!("work.{k}: {r}"))
    };
    let passes = r["work"]["passes"].as_u64().expect("passes");
    if cull == "passes" || cull == "early-out" {
        assert_eq!(r["culling"], cull, "{workload}: how it was culled");
    }
    (
        work("fragments") / covered,
        work("evaluations") / covered,
        passes,
    )
}

/// What culling saves, counted rather than timed: a 16-layer block of touching band-8
/// fODFs seen head-on makes at most twice the root isolations per covered pixel of its
/// front layer alone, culled in passes (1.4 times measured; 5.3 times without culling)
/// or by early outs (1.0 times). In passes it launches at most 1.6 times the front
/// layer's fragments per covered pixel (1.42 measured; 1.75 when the later passes'
/// second stages ran every fragment of the first); with early outs it launches every
/// fragment of one pass, as without culling, and saves their root isolations (which
/// only a device that jumps over code no pixel of a batch runs turns into time).
#[test]
fn a_culled_block_costs_at_most_twice_its_front_layer_per_covered_pixel() {
    let dir = fresh_dir("visibility-work");
    let (front_fragments, front_evaluations, front_passes) =
        work_per_pixel(&dir, "block:16:16:1:8", "occluded");
    assert_eq!(front_passes, 1, "the front layer is one pass");
    let (off_fragments, off_evaluations, off_passes) =
        work_per_pixel(&dir, "block:16:16:16:8", "off");
    assert_eq!(off_passes, 1, "--cull off draws one pass");
    assert!(
        off_evaluations / front_evaluations > 4.0,
        "without culling the block makes {off_evaluations:.2} evaluations per covered pixel"
    );
    for cull in ["passes", "early-out"] {
        let (fragments, evaluations, passes) = work_per_pixel(&dir, "block:16:16:16:8", cull);
        if cull == "passes" {
            assert!(passes >= 2, "the block is drawn in {passes} passes");
        } else {
            assert_eq!(passes, 1, "early outs draw one pass");
        }
        let ratio = evaluations / front_evaluations;
        assert!(
            ratio <= 2.0,
            "--cull {cull}: the block makes {evaluations:.2} evaluations per covered pixel, \
             {ratio:.2} times the front layer's {front_evaluations:.2}"
        );
        if cull == "early-out" {
            assert_eq!(
                fragments, off_fragments,
                "early outs launch the fragments of one pass"
            );
            continue;
        }
        let ratio = fragments / front_fragments;
        assert!(
            ratio <= 1.6,
            "--cull {cull}: the block launches {fragments:.2} fragments per covered pixel, \
             {ratio:.2} times the front layer's {front_fragments:.2} (the {off_fragments:.2} \
             of one pass)"
        );
    }
}

/// `glyphcast bench`'s counters of one 320x320 frame of the scene file `scene` with
/// `cull`: evaluations per covered pixel, the passes, and how it was culled.
fn scene_work(dir: &std::path::Path, scene: &std::path::Path, cull: &str) -> (f64, u64, String) {
    let r = bench_result(dir, &[text(scene)], cull, ("320", "320"));
    let covered = r["covered_pixels"].as_f64().expect("covered pixels");
    let evaluations = r["work"]["evaluations"].as_f64().expect("evaluations");
    let passes = r["work"]["passes"].as_u64().expect("passes");
    let culling = r["culling"].as_str().expect("culling").to_owned();
    (evaluations / covered, passes, culling)
}

/// DIPY's CSD block (small_64D's 10 x 10 x 10 voxels, fitted by `glyphcast fit` as a DIPY
/// user does), with the default sizes and with `--norm per-glyph`: its glyphs overlap on
/// screen (hidden work), so each explicit `--cull` is applied (early outs: fewer
/// evaluations per covered pixel than `--cull off`; passes: two or more), each to the
/// same depth map as `--cull off`; the default takes the early outs where the device
/// jumps over code no pixel runs (Mesa 25, GPUs: fewer evaluations than `--cull off`),
/// and on a device that runs it masked (Mesa 22.3) draws one pass and says why.
#[test]
fn the_dipy_block_is_culled_as_asked_and_says_so() {
    let dir = fresh_dir("visibility-dipy-block");
    let fit = crate::common::dipy_csd_fit();
    for norm in ["sqrt", "per-glyph"] {
        let scene = dir.join(format!("block-{norm}.json"));
        let mut depths = Vec::new();
        let mut off = 0.0;
        for cull in ["off", "occluded", "early-out", "passes"] {
            let (png, npy) = (dir.join("block.png"), dir.join(format!("block-{cull}.npy")));
            let run = glyphcast(&[
                "render",
                "--sh",
                text(&fit),
                "--block",
                "--norm",
                norm,
                "--cull",
                cull,
                "--width",
                "320",
                "--height",
                "320",
                "--save-scene",
                text(&scene),
                "-o",
                text(&png),
                "--depth-out",
                text(&npy),
            ]);
            let stderr = String::from_utf8_lossy(&run.stderr);
            assert!(run.status.success(), "{norm}, --cull {cull}: {stderr}");
            let line = stderr
                .lines()
                .find(|l| l.starts_with("culling: "))
                .unwrap_or_else(|| panic!("no culling line: {stderr}"))
                .to_owned();
            depths.push(std::fs::read(&npy).expect("the depth map"));
            assert!(
                depths[0] == depths[depths.len() - 1],
                "{norm}, --cull {cull}: {line}"
            );
            let (evaluations, passes, culling) = scene_work(&dir, &scene, cull);
            if cull == "off" {
                off = evaluations;
            }
            let what = format!(
                "{norm}, --cull {cull}: {line}; {evaluations:.2} evaluations per covered pixel, {off:.2} without culling"
            );
            match (cull, culling.as_str()) {
                ("off", _) => assert_eq!(passes, 1, "{what}"),
                ("early-out", _) | ("occluded", "early-out") => {
                    assert_eq!(culling, "early-out", "{what}");
                    assert!(evaluations < off, "{what}");
                    assert!(line.ends_with(": early outs (1 pass)"), "{what}");
                }
                ("passes", _) => {
                    assert!(passes >= 2, "{what}");
                    assert!(line.ends_with(" passes"), "{what}");
                }
                _ => assert!(
                    line.contains("passes pay from 3 layers of glyphs, the frame has fewer"),
                    "{what}"
                ),
            }
        }
    }
}
