//! The compute ray caster (`--path compute`) against the float64 reference and against
//! the fragment path (the same exact root isolation, glsl/exact_root.glsl, behind proxy
//! boxes): on the accuracy suite (a camera inside a glyph's box among its scenes), on a
//! dense generated fODF field, on a stack of overlapping glyphs deeper than one dispatch's
//! walk (front-to-back order and slices), with the stack split into parts by a small
//! storage buffer limit, and with two glyph sets of different layouts.
//!
//! Both paths run the same float32 code on the same pixel rays, so they should agree
//! to the bit on almost every pixel: the tolerances below allow float32 rounding of the
//! distance (1e-5 of the glyph scale) and one unit of the 8-bit sRGB encoding (the
//! compute shader encodes it itself, the colour target's conversion may round the
//! other way), and no pixel may be covered by one path and not the other.
use crate::common;
use glam::DVec3;
use glyphcast::accuracy::suite;
use glyphcast::bench::workload;
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::render::tiles::WALK_PER_DISPATCH;
use glyphcast::render::{RenderPath, RenderSettings};
use glyphcast::scene::Scene;
use glyphcast::vk::Gpu;

const SIZE: u32 = 128;

fn settings(path: RenderPath) -> RenderSettings {
    RenderSettings {
        path,
        ..Default::default()
    }
}

/// Compute against the reference: no holes, no false hits, float32 depth.
fn assert_accurate(name: &str, r: &common::Rendered) {
    let c = r.comparison;
    eprintln!("{name} (compute): {c}");
    assert!(c.covered > 0, "{name}: nothing to compare: {c}");
    if c.holes != 0 || c.false_hits != 0 || c.median_error >= 1e-4 {
        common::save_failure_images(&format!("{name}-compute"), r);
        panic!("{name}: {c}");
    }
}

/// Compute against fragment, pixel by pixel.
fn assert_same_image(name: &str, compute: &RenderedImage, fragment: &RenderedImage, scale: f64) {
    let mut coverage = 0;
    let mut far = 0;
    let mut colour = 0;
    for (p, (c, f)) in compute.distance.iter().zip(&fragment.distance).enumerate() {
        match (c.is_nan(), f.is_nan()) {
            (true, true) => {}
            (false, false) => {
                far += usize::from(((c - f) as f64).abs() > 1e-5 * scale);
            }
            _ => coverage += 1,
        }
        let (a, b) = (
            &compute.rgba[4 * p..4 * p + 4],
            &fragment.rgba[4 * p..4 * p + 4],
        );
        colour += usize::from(a.iter().zip(b).any(|(x, y)| x.abs_diff(*y) > 1));
    }
    eprintln!(
        "{name}: compute and fragment differ in coverage {coverage}, distance {far}, colour {colour}"
    );
    if coverage + far + colour != 0 {
        let dir = common::output_dir();
        for (path, image) in [("compute", compute), ("fragment", fragment)] {
            let _ = glyphcast::io::png::write_png_rgba8(
                &dir.join(format!("{name}-{path}.png")),
                image.width,
                image.height,
                &image.rgba,
            );
        }
        panic!("{name}: the paths differ (images in {})", dir.display());
    }
}

/// Renders `scene` on both paths, checks the compute image against the reference and
/// against the fragment image; returns the compute image.
fn check_scene(
    gpu: &Gpu,
    renderer: &mut HeadlessRenderer,
    name: &str,
    scene: &Scene,
) -> RenderedImage {
    let r = common::render_and_compare(gpu, renderer, scene, &settings(RenderPath::Compute));
    assert_accurate(name, &r);
    let fragment =
        common::render_and_compare(gpu, renderer, scene, &settings(RenderPath::Fragment));
    assert_same_image(name, &r.image, &fragment.image, r.scale);
    r.image
}

#[test]
fn compute_matches_reference_and_fragment_on_the_accuracy_suite() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for entry in suite::suite(SIZE) {
        check_scene(&gpu, &mut renderer, entry.name, &entry.scene);
    }
}

/// `--path auto` (the default) takes the fragment path on lavapipe, a CPU device: the
/// same image, bit for bit, as the fragment path asked for, and the image says so.
#[test]
fn auto_takes_the_fragment_path_on_lavapipe() {
    let gpu = common::gpu();
    assert_eq!(
        gpu.context().device_type(),
        ash::vk::PhysicalDeviceType::CPU,
        "the tests run on lavapipe"
    );
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let scene = workload::fodf(64, 8, 160, 120).expect("workload");
    let auto = common::render_and_compare(&gpu, &mut renderer, &scene, &settings(RenderPath::Auto));
    let fragment =
        common::render_and_compare(&gpu, &mut renderer, &scene, &settings(RenderPath::Fragment));
    assert_eq!(auto.image.path, RenderPath::Fragment);
    assert_eq!(auto.image.rgba, fragment.image.rgba);
    assert_eq!(common::differing_distances(&auto.image, &fragment.image), 0);
    let compute =
        common::render_and_compare(&gpu, &mut renderer, &scene, &settings(RenderPath::Compute));
    assert_eq!(compute.image.path, RenderPath::Compute);
}

/// The compute ray caster's walk takes subgroup votes (glsl/raycast_exact.comp). A
/// device whose compute shaders lack them (lavapipe's have them: its context is told
/// otherwise here) gets the fragment path from `auto`, even as a GPU, and a clear
/// refusal, not a panic or a validation error, when the compute path is asked for.
#[test]
fn auto_takes_the_fragment_path_where_compute_shaders_cannot_vote() {
    use glyphcast::glyph::{GlyphShape, Symmetry, TensorLayout};
    use glyphcast::render::Method;
    let gpu = common::gpu();
    assert!(
        gpu.context().compute_votes(),
        "lavapipe's compute shaders vote"
    );
    let as_gpu = gpu
        .context()
        .clone()
        .with_device_type(ash::vk::PhysicalDeviceType::DISCRETE_GPU);
    let polynomial = [GlyphShape::Polynomial];
    assert_eq!(
        RenderPath::Auto.on_context(&as_gpu, Method::Exact, polynomial),
        RenderPath::Compute
    );
    let mute = as_gpu.clone().without_compute_votes();
    assert_eq!(
        RenderPath::Auto.on_context(&mute, Method::Exact, polynomial),
        RenderPath::Fragment
    );
    assert_eq!(
        RenderPath::Compute.on_context(&mute, Method::Exact, polynomial),
        RenderPath::Compute,
        "a path asked for by name stays asked for"
    );
    let layout = TensorLayout {
        order: 8,
        symmetry: Symmetry::Symmetric,
    };
    let mut pass = glyphcast::render::compute::ComputeRayCastPass::new(&mute).expect("pass");
    let error = pass
        .pipeline(layout)
        .expect_err("no compute pipeline without votes");
    let message = error.to_string();
    assert!(
        message.contains("subgroup vote") && message.contains("--path fragment"),
        "{message}"
    );
    let mut pass = glyphcast::render::compute::ComputeRayCastPass::new(&as_gpu).expect("pass");
    pass.pipeline(layout)
        .expect("the pipeline where the device votes");
}

#[test]
fn compute_matches_on_a_dense_fodf_field() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let scene = workload::fodf(64, 8, 160, 120).expect("workload");
    check_scene(&gpu, &mut renderer, "fodf-64", &scene);
}

/// More glyphs than one dispatch walks, overlapping along the view: crossings of two
/// fibres, one behind the other and slightly offset, seen from the front so that every
/// pixel's list is longer than WALK_PER_DISPATCH and front-to-back order decides what
/// is seen.
fn glyph_stack() -> Scene {
    let count = WALK_PER_DISPATCH as usize + 12;
    let mut scene = suite::thin_crossing_lobes(SIZE);
    let eye = DVec3::new(0.3, -6.0, 0.4);
    let fwd = (-eye).normalize();
    let centers: Vec<DVec3> = (0..count)
        .map(|k| {
            let t = k as f64 / count as f64;
            DVec3::new(0.25 * (7.0 * t).sin(), 0.0, 0.25 * (5.0 * t).cos())
                + fwd * (0.12 * k as f64)
        })
        .collect();
    let tensors = (0..count)
        .map(|k| {
            fibre_tensor(
                6,
                &[
                    (direction(20.0 * k as f64, 10.0), 1.0),
                    (direction(20.0 * k as f64 + 80.0, -30.0), 0.8),
                ],
            )
        })
        .collect();
    scene.glyph_sets = vec![glyph_set(symmetric(6), centers, 0.5, tensors)];
    scene.camera.eye = eye;
    scene
}

#[test]
fn compute_walks_a_stack_deeper_than_one_dispatch_front_to_back() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let scene = glyph_stack();
    let whole = check_scene(&gpu, &mut renderer, "stack", &scene);
    assert!(
        whole.draws >= 2,
        "{} dispatches: the stack must take slices",
        whole.draws
    );

    // Parts of 10 glyphs each (order 6: 28 coefficients, 112 bytes a glyph).
    renderer
        .compute_pass_mut()
        .set_storage_buffer_limit(Some(10 * 112));
    let sets = prepare_scene(&scene, 0.0).expect("prepare");
    let (w, h) = (scene.image.width, scene.image.height);
    let parts = renderer
        .render_view(
            &gpu,
            &sets,
            &glyphcast::FrameView::new(&scene.camera, w, h),
            &settings(RenderPath::Compute),
        )
        .expect("render in parts");
    renderer.compute_pass_mut().set_storage_buffer_limit(None);
    assert!(parts.draws > whole.draws, "{} dispatches", parts.draws);
    assert_eq!(parts.rgba, whole.rgba, "parts change the image");
    let same = parts
        .distance
        .iter()
        .zip(&whole.distance)
        .all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(same, "parts change the distances");
}

/// Walks longer than one dispatch's root isolations: 100 copies of one crossing, stacked
/// along the view axis through their centres, and behind them, in the same glyph set, a
/// glyph of many fibres that has no gaps. Perspective keeps the gaps between the
/// crossing's lobes on the same screen rays layer after layer, so a ray through a gap
/// near the centre enters every box of the stack without a hit (a root isolation each,
/// 100 in all) before it meets the glyph behind: its walk goes on over four dispatches of
/// WALK_PER_DISPATCH (32) root isolations, each from where the one before stopped. A
/// walk that did not go on would leave holes there (against the reference and the
/// fragment path).
#[test]
fn compute_walks_go_on_over_dispatches_through_the_gaps_of_a_deep_stack() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let layers = 100;
    assert!(layers > 3 * WALK_PER_DISPATCH as usize);
    let mut scene = suite::thin_crossing_lobes(SIZE);
    let crossing = fibre_tensor(
        6,
        &[(direction(0.0, 0.0), 1.0), (direction(0.0, 90.0), 1.0)],
    );
    let mut centers: Vec<DVec3> = (0..layers)
        .map(|k| DVec3::new(0.0, 0.05 * k as f64, 0.0))
        .collect();
    let mut coeffs = vec![crossing; layers];
    // Fibres every 45 degrees at four elevations and the poles: a lumpy ball.
    let mut fibres = vec![(DVec3::Z, 1.0), (-DVec3::Z, 1.0)];
    for elev in [-60.0, -20.0, 20.0, 60.0] {
        fibres.extend((0..8).map(|k| (direction(45.0 * f64::from(k), elev), 1.0)));
    }
    centers.push(DVec3::new(0.0, 9.0, 0.0));
    coeffs.push(fibre_tensor(6, &fibres));
    let mut set = glyph_set(symmetric(6), centers, 0.5, coeffs);
    set.scales[layers] = 0.6;
    scene.glyph_sets = vec![set];
    scene.camera.eye = DVec3::new(0.0, -4.0, 0.0);
    scene.camera.target = DVec3::ZERO;
    let image = check_scene(&gpu, &mut renderer, "deep-stack", &scene);
    assert!(image.draws >= 4, "{} dispatches", image.draws);
    // The glyph behind (beyond 10 from the eye; the last crossing lies at 9) shows in the
    // gaps.
    let through = image.distance.iter().filter(|d| **d > 10.0).count();
    assert!(through > 100, "{through} pixels of the glyph behind");
}

/// Two glyph sets of different tensor layouts (a symmetric order-4 and the non-symmetric
/// stiffness tensor), interleaved in depth: each set is its own dispatch, and the second
/// composes with the first by distance.
#[test]
fn compute_composes_glyph_sets_of_different_layouts() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let mut scene = suite::stiffness(SIZE);
    let crossing = fibre_tensor(
        4,
        &[(direction(0.0, 0.0), 1.0), (direction(90.0, 0.0), 0.7)],
    );
    let centers = vec![DVec3::new(0.2, 0.3, 0.1), DVec3::new(-0.3, -0.4, -0.1)];
    scene.glyph_sets.push(glyph_set(
        symmetric(4),
        centers,
        0.6,
        vec![crossing.clone(), crossing],
    ));
    let sets = prepare_scene(&scene, 0.0).expect("prepare");
    assert_eq!(sets.len(), 2);
    assert_ne!(sets[0].layout, sets[1].layout);
    check_scene(&gpu, &mut renderer, "two-layouts", &scene);
}

/// An engine's renderer made for the compute path refuses to draw a frame whose
/// dispatches it did not record (`record_compute`), instead of composing stale outputs;
/// once they are recorded, `record` draws.
#[test]
fn the_engine_compute_path_draws_only_after_its_dispatches() {
    use ash::vk;
    use glyphcast::render::component::{GlyphRenderer, RendererDesc};
    use glyphcast::render::host_view::{HostView, look_at, perspective};
    use glyphcast::render::raycast::{PassOptions, TargetFormats};
    let gpu = common::gpu();
    let desc = RendererDesc {
        formats: TargetFormats {
            color: vk::Format::R8G8B8A8_SRGB,
            depth: vk::Format::D32_SFLOAT,
            distance: None,
        },
        options: PassOptions::default(),
        frames_in_flight: 2,
        settings: settings(RenderPath::Compute),
    };
    let mut renderer = GlyphRenderer::new(gpu.context(), &desc).expect("renderer");
    assert_eq!(renderer.path(), RenderPath::Compute);
    let scene = workload::fodf(16, 8, 64, 48).expect("workload");
    let sets = prepare_scene(&scene, 0.0).expect("prepare");
    renderer.set_glyphs(&sets).expect("glyphs");
    let camera = &scene.camera;
    let view = HostView::whole(
        look_at(camera.eye, camera.target, camera.up),
        perspective(
            0.6,
            64.0 / 48.0,
            0.1,
            None,
            glyphcast::DepthConvention::Reversed,
        ),
        64,
        48,
    );
    renderer.set_view(0, &view).expect("view");
    let d = gpu.device();
    // SAFETY: a pool and a buffer of this device, freed below; nothing is submitted.
    unsafe {
        let pool = d
            .create_command_pool(
                &vk::CommandPoolCreateInfo::default().queue_family_index(gpu.queue_family),
                None,
            )
            .expect("pool");
        let cmd = d
            .allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default()
                    .command_pool(pool)
                    .command_buffer_count(1),
            )
            .expect("buffer")[0];
        d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())
            .expect("begin");
        let error = renderer.record(cmd, 0).expect_err("no dispatches yet");
        assert!(error.to_string().contains("record_compute"), "{error}");
        renderer.record_compute(cmd, 0).expect("dispatches");
        let _ = d.end_command_buffer(cmd);
        d.destroy_command_pool(pool, None);
    }
    assert!(
        gpu.validation_errors().is_empty(),
        "{:?}",
        gpu.validation_errors()
    );
}
