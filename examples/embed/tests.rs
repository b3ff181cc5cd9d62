//! The example engine under synchronization validation, against glyphcast's headless
//! renderer of the same camera; `cargo test --example embed` runs these.
use super::*;
use glyphcast::glyph::reference::reference_depth;
use glyphcast::{Gpu, GpuOptions, HeadlessRenderer, RenderedImage};

fn options(depth: DepthConvention, samples: u32) -> Options {
    Options {
        frames: 60,
        in_flight: 3,
        depth,
        depth_format: DEPTH_FORMAT,
        samples,
        allocator: MemorySource::GpuAllocator,
        validation: Validation::Sync,
        screenshot: None,
        plane: true,
        viewport: None,
        path: RenderPath::Fragment,
        as_gpu: false,
        dispatches: true,
        block: false,
        cull: Culling::Occluded,
        storage_limit: None,
        fragment_stores: true,
        proxy: Proxy::Box,
    }
}

fn headless(run: &Run, samples: u32) -> RenderedImage {
    let gpu = Gpu::headless(&GpuOptions {
        validation: true,
        device: std::env::var("GLYPHCAST_DEVICE").ok(),
    })
    .expect("a Vulkan device with validation");
    let mut renderer = HeadlessRenderer::new(&gpu).expect("headless renderer");
    // The engine's clear colour (linear, as a clear value of an sRGB image is).
    let settings = RenderSettings {
        samples,
        background: [0.55, 0.65, 0.8, 1.0],
        ..RenderSettings::default()
    };
    let image = renderer
        .render_view(
            &gpu,
            &run.sets,
            &glyphcast::FrameView::new(&run.camera, WIDTH, HEIGHT),
            &settings,
        )
        .expect("headless render");
    assert_eq!(gpu.validation_errors(), Vec::<String>::new());
    image
}

/// The engine's last frame against the headless render of its camera (glyphs) and the
/// analytic plane, at every pixel but those next to the plane's border and those where
/// plane and glyph lie within `CROSSING` of each other.
#[derive(Debug, Default)]
struct GlyphMatch {
    /// Pixels judged.
    judged: usize,
    /// Of those, pixels where a glyph is in front.
    glyph: usize,
    /// Pixels where the engine shows a glyph and the headless render none, or the other
    /// way round.
    coverage_differs: usize,
    /// The largest depth difference at visible glyphs, in units of the glyph scale.
    max_error: f64,
    /// The median difference from the float64 reference (exact intersections) at visible
    /// glyphs where it has a hit too, in units of the glyph scale.
    median_reference_error: f64,
}

/// Plane and glyph closer than this (units of the glyph scale) are not judged: which one
/// a depth test keeps there depends on float32 depth rounding.
const CROSSING: f64 = 1e-3;

fn glyph_match(run: &Run, reference: &RenderedImage) -> GlyphMatch {
    let engine = depth_to_distance(&run.depth, &run.camera, &run.projection, (WIDTH, HEIGHT));
    let scale = run
        .sets
        .iter()
        .flat_map(|s| &s.world)
        .map(|g| g.scale * g.bound)
        .fold(0.0, f64::max);
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let plane: Vec<f64> = (0..w * h)
        .map(|k| {
            let ray = run
                .camera
                .ray((k % w) as u32, (k / w) as u32, WIDTH, HEIGHT);
            SQUARE.hit(ray.origin, ray.dir).unwrap_or(f64::NAN)
        })
        .collect();
    let world: Vec<_> = run.sets.iter().flat_map(|s| s.world.clone()).collect();
    let exact = reference_depth(&world, &run.camera, WIDTH, HEIGHT);
    let mut reference_errors = Vec::new();
    let mut m = GlyphMatch::default();
    for k in 0..w * h {
        let (x, y) = (k % w, k / w);
        let plane_border = (y.saturating_sub(1)..=(y + 1).min(h - 1))
            .flat_map(|ny| (x.saturating_sub(1)..=(x + 1).min(w - 1)).map(move |nx| ny * w + nx))
            .any(|n| plane[n].is_nan() != plane[k].is_nan());
        let glyph = reference.distance[k] as f64;
        if plane_border || (glyph - plane[k]).abs() < CROSSING * scale {
            continue;
        }
        m.judged += 1;
        // The nearer of glyph and plane is what the engine's depth buffer should hold.
        let glyph_in_front = !glyph.is_nan() && (plane[k].is_nan() || plane[k] >= glyph);
        let engine_glyph = !engine[k].is_nan()
            && (plane[k].is_nan() || engine[k] < plane[k] - 0.5 * CROSSING * scale);
        if glyph_in_front != engine_glyph {
            m.coverage_differs += 1;
        } else if glyph_in_front {
            m.glyph += 1;
            m.max_error = m.max_error.max((engine[k] - glyph).abs() / scale);
            if !exact[k].is_nan() {
                reference_errors.push((engine[k] - exact[k]).abs() / scale);
            }
        }
    }
    reference_errors.sort_by(f64::total_cmp);
    m.median_reference_error = reference_errors[reference_errors.len() / 2];
    m
}

/// Pixels whose RGBA differ between two pictures.
fn differing(a: &[u8], b: &[u8]) -> usize {
    a.chunks(4).zip(b.chunks(4)).filter(|(p, q)| p != q).count()
}

fn save(name: &str, rgba: &[u8]) {
    let path = std::env::temp_dir().join(format!("embed-{name}.png"));
    let _ = glyphcast::io::png::write_png_rgba8(&path, WIDTH, HEIGHT, rgba);
    eprintln!("image: {}", path.display());
}

/// 60 frames, 3 in flight, camera moving every frame and the glyphs replaced once, under
/// synchronization validation: no message, the retired glyphs released, and the last
/// frame's glyphs where glyphcast's headless renderer puts them, in both depth
/// conventions, which give the same picture.
fn frames_in_flight_match_headless(samples: u32) {
    let standard = run(&options(DepthConvention::Standard, samples)).expect("standard run");
    let reversed = run(&options(DepthConvention::Reversed, samples)).expect("reversed run");
    for (name, r) in [("standard", &standard), ("reversed", &reversed)] {
        assert_eq!(r.validation, Vec::<String>::new(), "{name}");
        assert_eq!(
            r.retired_at_end, 0,
            "{name}: the replaced glyphs were released"
        );
    }
    // The same picture: the rays and colours do not depend on the depth convention, and
    // at this size no pixel of the plane-glyph crossings is decided differently by the
    // two depth roundings (should one be, it is saved for a look).
    let changed = differing(&standard.rgba, &reversed.rgba);
    if changed > 0 {
        save(&format!("standard-{samples}"), &standard.rgba);
        save(&format!("reversed-{samples}"), &reversed.rgba);
    }
    assert_eq!(changed, 0, "pixels differ between the conventions");
    if samples > 1 {
        // Depth of sample 0 lies off the pixel centre, where headless rays go: the
        // multisampled glyphs are held to the supersampled render by the edge test.
        return;
    }
    let reference = headless(&standard, 1);
    for (name, r) in [("standard", &standard), ("reversed", &reversed)] {
        let m = glyph_match(r, &reference);
        eprintln!("{name}: {m:?}");
        assert!(m.judged > 1000 && m.glyph > 300, "{name}: {m:?}");
        assert_eq!(m.coverage_differs, 0, "{name}: {m:?}");
        assert!(m.max_error < 1e-4, "{name}: {m:?}");
        // The ray caster's error at default settings (tests/depth_accuracy.rs).
        assert!(m.median_reference_error < 1e-3, "{name}: {m:?}");
    }
}

/// The hull's outline (`proxy: hull`) and the pieces (`proxy: pieces`, each glyph's
/// polytope cut into its box's octants: the component does not bound pieces) in the
/// engine's pass: 60 frames, 3 in flight, the glyphs replaced halfway, in both depth
/// conventions, under synchronization validation: no message, and the glyphs where the
/// headless renderer (with boxes) puts them, in front of and behind the plane.
#[test]
fn the_hull_outline_draws_the_headless_picture() {
    let mut reference: Option<RenderedImage> = None;
    for proxy in [Proxy::Hull, Proxy::Pieces] {
        for depth in [DepthConvention::Standard, DepthConvention::Reversed] {
            let r = run(&Options {
                proxy,
                ..options(depth, 1)
            })
            .expect("run");
            assert_eq!(r.validation, Vec::<String>::new(), "{proxy:?} {depth:?}");
            let reference = reference.get_or_insert_with(|| headless(&r, 1));
            let m = glyph_match(&r, reference);
            assert!(
                m.judged > 1000 && m.glyph > 300,
                "{proxy:?} {depth:?}: {m:?}"
            );
            assert_eq!(m.coverage_differs, 0, "{proxy:?} {depth:?}: {m:?}");
            assert!(m.max_error < 1e-4, "{proxy:?} {depth:?}: {m:?}");
        }
    }
}

/// `--path compute`: 24 frames, 3 in flight, the glyphs replaced halfway, under
/// synchronization validation, in both depth conventions: no message, the picture of
/// the fragment path (its sRGB bytes within one unit: the compute shader encodes its
/// colour itself) and the same depth, and the glyphs where the headless renderer puts
/// them, in front of and behind the plane.
#[test]
fn the_compute_path_draws_the_fragment_path_picture() {
    for depth in [DepthConvention::Standard, DepthConvention::Reversed] {
        let base = Options {
            frames: 24,
            ..options(depth, 1)
        };
        let fragment = run(&base).expect("fragment run");
        let compute = run(&Options {
            path: RenderPath::Compute,
            ..base
        })
        .expect("compute run");
        assert_eq!(compute.validation, Vec::<String>::new(), "{depth:?}");
        let colour = compute
            .rgba
            .iter()
            .zip(&fragment.rgba)
            .filter(|(a, b)| a.abs_diff(**b) > 1)
            .count();
        if colour > 0 {
            save(&format!("compute-{depth:?}"), &compute.rgba);
            save(&format!("fragment-{depth:?}"), &fragment.rgba);
        }
        assert_eq!(colour, 0, "{depth:?}: colours differ");
        let depths = compute
            .depth
            .iter()
            .zip(&fragment.depth)
            .filter(|(a, b)| (*a - *b).abs() > 1e-6)
            .count();
        assert_eq!(depths, 0, "{depth:?}: depths differ");
        let m = glyph_match(&compute, &headless(&compute, 1));
        eprintln!("compute {depth:?}: {m:?}");
        assert!(m.judged > 1000 && m.glyph > 300, "{depth:?}: {m:?}");
        assert_eq!(m.coverage_differs, 0, "{depth:?}: {m:?}");
        assert!(m.max_error < 1e-4, "{depth:?}: {m:?}");
    }
}

/// Early outs in the engine's pass (`cull: early-out`, which `occluded` takes on a
/// device that jumps over code no pixel runs): a block of 8 x 8 x 12 fODFs seen head-on,
/// 6 frames, 3 in flight, under synchronization validation, in both depth conventions,
/// gives the picture and the depth of `cull: off` bit for bit, whether the engine
/// clears the known depths before its rendering (`record_compute`, which the early outs
/// need) or not (the frame is then drawn as without culling).
#[test]
fn early_outs_in_the_engine_pass_keep_every_pixel() {
    for depth in [DepthConvention::Standard, DepthConvention::Reversed] {
        let base = Options {
            frames: 6,
            plane: false,
            block: true,
            ..options(depth, 1)
        };
        let off = run(&Options {
            cull: Culling::Off,
            ..base.clone()
        })
        .expect("cull off");
        assert_eq!(off.culling, Culling::Off, "{depth:?}");
        for dispatches in [true, false] {
            let early = run(&Options {
                cull: Culling::EarlyOut,
                dispatches,
                ..base.clone()
            })
            .expect("early outs");
            let name = format!("{depth:?}, record_compute: {dispatches}");
            assert_eq!(early.validation, Vec::<String>::new(), "{name}");
            assert_eq!(early.culling, Culling::EarlyOut, "{name}");
            let glyph = off.depth.iter().filter(|&&z| z != off.depth[0]).count();
            assert!(glyph > 2000, "{name}: {glyph} pixels show the block");
            let changed = differing(&off.rgba, &early.rgba);
            if changed > 0 {
                save("cull-off", &off.rgba);
                save("early-outs", &early.rgba);
            }
            assert_eq!(changed, 0, "{name}: pixels differ with early outs");
            let depths = |r: &Run| r.depth.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
            assert!(depths(&off) == depths(&early), "{name}: the depth differs");
        }
    }
}

/// A host whose device was created without fragmentStoresAndAtomics (glyphcast asks a
/// host only for Vulkan 1.3 dynamic rendering): 30 frames, 3 in flight, the glyphs
/// replaced once, early outs asked for, under synchronization validation, in both depth
/// conventions. No validation message (the fragment shaders write no buffer there), the
/// frame drawn without culling, and the picture and depth of a device that has the
/// feature, bit for bit: for the six glyphs over the plane and for the block.
#[test]
fn a_device_without_fragment_stores_draws_the_glyphs_without_culling() {
    for depth in [DepthConvention::Standard, DepthConvention::Reversed] {
        for block in [false, true] {
            let base = Options {
                frames: 30,
                block,
                plane: !block,
                cull: Culling::EarlyOut,
                ..options(depth, 1)
            };
            let with = run(&base).expect("a device with fragment stores");
            let without = run(&Options {
                fragment_stores: false,
                ..base.clone()
            })
            .expect("a device without fragment stores");
            let name = format!("{depth:?}, block: {block}");
            assert_eq!(without.validation, Vec::<String>::new(), "{name}");
            assert_eq!(with.validation, Vec::<String>::new(), "{name}");
            assert_eq!(without.culling, Culling::Off, "{name}");
            if block {
                assert_eq!(with.culling, Culling::EarlyOut, "{name}");
            }
            let glyph = with.depth.iter().filter(|&&z| z != with.depth[0]).count();
            assert!(
                glyph > 2000,
                "{name}: {glyph} pixels show glyphs or the plane"
            );
            let changed = differing(&with.rgba, &without.rgba);
            if changed > 0 {
                save("with-fragment-stores", &with.rgba);
                save("without-fragment-stores", &without.rgba);
            }
            assert_eq!(changed, 0, "{name}: pixels differ");
            let depths = |r: &Run| r.depth.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
            assert!(
                depths(&with) == depths(&without),
                "{name}: the depth differs"
            );
        }
    }
}

/// A scissor whose known depths would exceed a storage buffer (the device's
/// maxStorageBufferRange, here a cap standing in for it) is drawn without early outs:
/// `culling` says so, no validation message, the picture and depth of `cull: off`.
#[test]
fn a_scissor_too_large_for_its_known_depths_is_drawn_without_early_outs() {
    let base = Options {
        frames: 4,
        plane: false,
        block: true,
        ..options(DepthConvention::Reversed, 1)
    };
    let off = run(&Options {
        cull: Culling::Off,
        ..base.clone()
    })
    .expect("cull off");
    // The known depths take 16 + 4 bytes a pixel of the scissor (the whole target).
    let capped = run(&Options {
        cull: Culling::EarlyOut,
        storage_limit: Some(4 * u64::from(WIDTH * HEIGHT)),
        ..base.clone()
    })
    .expect("early outs under the cap");
    assert_eq!(capped.validation, Vec::<String>::new());
    assert_eq!(capped.culling, Culling::Off, "drawn without early outs");
    assert_eq!(differing(&off.rgba, &capped.rgba), 0, "pixels differ");
    let depths = |r: &Run| r.depth.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
    assert!(depths(&off) == depths(&capped), "the depth differs");
    // Just above the cap's edge, the same scissor takes them.
    let fits = run(&Options {
        cull: Culling::EarlyOut,
        storage_limit: Some(16 + 4 * u64::from(WIDTH * HEIGHT)),
        ..base
    })
    .expect("early outs at the cap");
    assert_eq!(fits.culling, Culling::EarlyOut);
    assert_eq!(
        differing(&off.rgba, &fits.rgba),
        0,
        "pixels differ at the cap"
    );
}

/// `auto` (the default) on a device glyphcast is told is a GPU: with the engine
/// recording `record_compute`, the glyphs go to the compute path from the frame after
/// the first dispatches (and again after the slice step), without it the fragment path
/// draws every frame; both draw the fragment path's picture, with no validation message
/// (synchronization validation included).
#[test]
fn auto_takes_the_compute_path_where_the_engine_records_its_dispatches() {
    let base = Options {
        frames: 12,
        ..options(DepthConvention::Standard, 1)
    };
    let fragment = run(&base).expect("fragment run");
    assert_eq!(fragment.path, RenderPath::Fragment);
    let auto = |dispatches| Options {
        path: RenderPath::Auto,
        as_gpu: true,
        dispatches,
        ..base.clone()
    };
    for (dispatches, path) in [(true, RenderPath::Compute), (false, RenderPath::Auto)] {
        let r = run(&auto(dispatches)).expect("auto run");
        assert_eq!(
            r.validation,
            Vec::<String>::new(),
            "dispatches {dispatches}"
        );
        assert_eq!(r.path, path, "dispatches {dispatches}");
        let colour = r
            .rgba
            .iter()
            .zip(&fragment.rgba)
            .filter(|(a, b)| a.abs_diff(**b) > 1)
            .count();
        assert_eq!(colour, 0, "dispatches {dispatches}: colours differ");
        let depths = r
            .depth
            .iter()
            .zip(&fragment.depth)
            .filter(|(a, b)| (*a - *b).abs() > 1e-6)
            .count();
        assert_eq!(depths, 0, "dispatches {dispatches}: depths differ");
    }
}

#[test]
fn sixty_frames_three_in_flight_one_sample() {
    frames_in_flight_match_headless(1);
}

#[test]
fn sixty_frames_three_in_flight_four_samples() {
    frames_in_flight_match_headless(4);
}

/// Most engines' depth buffer has a stencil aspect (D24S8, D32S8), bound as the
/// rendering's depth and stencil attachment: the glyphs draw into it under
/// synchronization validation with no message, and the picture and depth are those of
/// the depth-only target, at one sample and at four.
#[test]
fn a_depth_stencil_target_draws_the_depth_target_picture() {
    for samples in [1, 4] {
        let depth_only = run(&options(DepthConvention::Standard, samples)).expect("D32 run");
        let with_stencil = run(&Options {
            depth_format: DEPTH_STENCIL_FORMAT,
            ..options(DepthConvention::Standard, samples)
        })
        .expect("D32S8 run");
        assert_eq!(with_stencil.validation, Vec::<String>::new(), "{samples}");
        assert_eq!(
            differing(&depth_only.rgba, &with_stencil.rgba),
            0,
            "{samples}"
        );
        assert_eq!(depth_only.depth, with_stencil.depth, "{samples}");
        let covered = with_stencil.depth.iter().filter(|&&z| z < 1.0).count();
        assert!(covered > 1000, "{samples}: {covered} pixels drawn");
    }
}

/// Mean difference (0-255, RGB) from the 16x supersampled headless render (drawn over
/// the engine's clear colour) at the glyph silhouettes: pixels whose 3 x 3 neighbourhood
/// holds both hits and misses of the reference's pixel-centre rays.
fn edge_error(rgba: &[u8], reference: &RenderedImage) -> (f64, usize) {
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let hit = |k: usize| !reference.distance[k].is_nan();
    let mut total = 0.0;
    let mut count = 0;
    for k in 0..w * h {
        let (x, y) = (k % w, k / w);
        let edge = (y.saturating_sub(1)..=(y + 1).min(h - 1))
            .flat_map(|ny| (x.saturating_sub(1)..=(x + 1).min(w - 1)).map(move |nx| ny * w + nx))
            .any(|n| hit(n) != hit(k));
        if !edge {
            continue;
        }
        count += 1;
        for c in 0..3 {
            let (p, q) = (rgba[4 * k + c] as f64, reference.rgba[4 * k + c] as f64);
            total += (p - q).abs() / 3.0;
        }
    }
    (total / count.max(1) as f64, count)
}

/// Multisampled glyph silhouettes: at 4 samples the edges are at least twice as close to
/// the 16x supersampled headless render as at 1 sample.
#[test]
fn four_samples_halve_the_edge_error() {
    let mut errors = Vec::new();
    let mut reference = None;
    for samples in [1, 4] {
        let r = run(&Options {
            frames: 3,
            in_flight: 2,
            plane: false,
            ..options(DepthConvention::Reversed, samples)
        })
        .expect("run");
        assert_eq!(r.validation, Vec::<String>::new());
        let reference = reference.get_or_insert_with(|| headless(&r, 16));
        let (error, edges) = edge_error(&r.rgba, reference);
        eprintln!("{samples} sample(s): mean edge error {error:.2} over {edges} pixels");
        assert!(edges > 100);
        save(&format!("msaa-{samples}"), &r.rgba);
        errors.push(error);
    }
    assert!(errors[1] * 2.0 <= errors[0], "{errors:?}");
}

/// Two threads record the same prepared renderer, frame 0, into their own command
/// buffers (from their own pools) at once; the two pictures are identical.
#[test]
fn two_threads_record_identical_pictures() {
    let engine = Engine::new(Validation::Sync, true).expect("engine");
    let depth = DepthConvention::Standard;
    // SAFETY: as in `run_on`: the context and renderer are dropped before the engine.
    let context = unsafe {
        DeviceContext::new(
            &engine.instance,
            engine.physical_device,
            engine.device.clone(),
            engine.allocator(),
        )
    };
    let settings = RenderSettings::default();
    let sets = prepare_scene(&scene(0), settings.offset as f64).expect("scene");
    let desc = RendererDesc {
        formats: TargetFormats {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            distance: None,
        },
        options: PassOptions {
            depth,
            ..PassOptions::default()
        },
        frames_in_flight: 1,
        settings,
    };
    let mut glyphs = GlyphRenderer::new(&context, &desc).expect("renderer");
    glyphs.set_glyphs(&sets).expect("glyphs");
    let (view, projection) = host_matrices(&camera(0), depth, extent().into());
    let view = HostView::whole(view, projection, WIDTH, HEIGHT);
    glyphs.set_view(0, &view).expect("view");
    let one = vk::SampleCountFlags::TYPE_1;
    let bytes = 4 * WIDTH as u64 * HEIGHT as u64;
    let pools: Vec<_> = (0..2)
        .map(|_| engine.create_command_pool().expect("pool"))
        .collect();
    let slots: Vec<_> = pools
        .iter()
        .map(|&pool| {
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            // SAFETY: the pool belongs to the device; freed with the pool.
            let cmd = unsafe { engine.device.allocate_command_buffers(&alloc) }.expect("cmd")[0];
            let readbacks = (
                engine.create_readback("colour", bytes).expect("readback"),
                engine.create_readback("depth", bytes).expect("readback"),
            );
            (
                Slot::new(&engine, cmd, (one, DEPTH_FORMAT)).expect("slot"),
                readbacks,
            )
        })
        .collect();
    std::thread::scope(|scope| {
        for (slot, (color, depth_readback)) in &slots {
            let (engine, glyphs) = (&engine, &glyphs);
            scope.spawn(move || {
                let begin = vk::CommandBufferBeginInfo::default();
                // SAFETY: each thread records its own command buffer of its own pool.
                unsafe { engine.device.begin_command_buffer(slot.cmd, &begin) }.expect("begin");
                record_frame(engine, slot, depth, |cmd| Ok(glyphs.record(cmd, 0)?))
                    .expect("record");
                record_readback(engine, slot, color, depth_readback);
                // SAFETY: as above.
                unsafe { engine.device.end_command_buffer(slot.cmd) }.expect("end");
            });
        }
    });
    let cmds: Vec<_> = slots.iter().map(|(slot, _)| slot.cmd).collect();
    let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
    // SAFETY: both recorded; waiting for idle before reading.
    unsafe {
        engine
            .device
            .queue_submit(engine.queue, &submit, vk::Fence::null())
            .expect("submit");
        engine.device.device_wait_idle().expect("wait");
    }
    let pictures: Vec<Vec<u8>> = slots
        .iter()
        .map(|(_, (color, _))| engine.read(color).expect("read").to_vec())
        .collect();
    let background = pictures[0]
        .chunks(4)
        .filter(|p| *p == &pictures[0][..4])
        .count();
    assert!(background < pictures[0].len() / 4 - 500, "glyphs are drawn");
    assert_eq!(differing(&pictures[0], &pictures[1]), 0);
    for (slot, (color, depth_readback)) in slots {
        engine.destroy_readback(color).expect("free");
        engine.destroy_readback(depth_readback).expect("free");
        slot.destroy(&engine).expect("free");
    }
    drop(glyphs);
    drop(context);
    for pool in pools {
        // SAFETY: the device is idle; the command buffers go with their pool.
        unsafe { engine.device.destroy_command_pool(pool, None) };
    }
    assert_eq!(engine.validation_messages(), Vec::<String>::new());
}

/// The host's viewport and scissor, a sub-rectangle of its target (an editor's view): the
/// glyphs inside it are the headless render at the rectangle's size, pixel for pixel
/// (coverage identical, depth within 1e-4 of the glyph scale), and nothing is drawn
/// outside it.
#[test]
fn a_sub_rectangle_viewport_draws_the_headless_picture_there() {
    let rect = vk::Rect2D {
        offset: vk::Offset2D { x: 40, y: 20 },
        extent: vk::Extent2D {
            width: 80,
            height: 60,
        },
    };
    let r = run(&Options {
        frames: 2,
        in_flight: 2,
        plane: false,
        viewport: Some(rect),
        ..options(DepthConvention::Standard, 1)
    })
    .expect("run");
    assert_eq!(r.validation, Vec::<String>::new());
    let (w, h) = (rect.extent.width, rect.extent.height);
    let inside = |k: usize| {
        let (x, y) = ((k as u32 % WIDTH) as i32, (k as u32 / WIDTH) as i32);
        (rect.offset.x..rect.offset.x + w as i32).contains(&x)
            && (rect.offset.y..rect.offset.y + h as i32).contains(&y)
    };
    let (sub, outside): (Vec<_>, Vec<_>) = (0..r.depth.len()).partition(|&k| inside(k));
    assert!(
        outside.iter().all(|&k| r.depth[k] == 1.0),
        "drawn outside the viewport"
    );
    let depth: Vec<f32> = sub.iter().map(|&k| r.depth[k]).collect();
    let engine = depth_to_distance(&depth, &r.camera, &r.projection, (w, h));
    let gpu = Gpu::headless(&GpuOptions {
        validation: true,
        device: std::env::var("GLYPHCAST_DEVICE").ok(),
    })
    .expect("a Vulkan device with validation");
    let mut renderer = HeadlessRenderer::new(&gpu).expect("headless renderer");
    let reference = renderer
        .render_view(
            &gpu,
            &r.sets,
            &glyphcast::FrameView::new(&r.camera, w, h),
            &RenderSettings::default(),
        )
        .expect("headless render");
    let scale = r
        .sets
        .iter()
        .flat_map(|s| &s.world)
        .map(|g| g.scale * g.bound);
    let scale = scale.fold(0.0, f64::max);
    let mut glyph = 0;
    for (k, &distance) in engine.iter().enumerate() {
        let expected = reference.distance[k] as f64;
        assert_eq!(distance.is_nan(), expected.is_nan(), "coverage at {k}");
        if !expected.is_nan() {
            glyph += 1;
            assert!((distance - expected).abs() < 1e-4 * scale, "depth at {k}");
        }
    }
    assert!(glyph > 300, "{glyph} glyph pixels");
}

/// glyphcast's buffers and images in the memory of a second `MemoryAllocator` (one
/// vkAllocateMemory per block), under synchronization validation with the glyphs
/// replaced while frames are in flight: no message, every block taken from it and given
/// back, and the frames equal to those drawn in gpu-allocator's memory.
#[test]
fn a_host_memory_allocator_draws_the_same_frames() {
    let base = Options {
        frames: 8,
        in_flight: 2,
        ..options(DepthConvention::Standard, 1)
    };
    let default = run(&base).expect("gpu-allocator run");
    let plain = run(&Options {
        allocator: MemorySource::Plain,
        ..base.clone()
    })
    .expect("plain run");
    assert_eq!(default.validation, Vec::<String>::new());
    assert_eq!(plain.validation, Vec::<String>::new());
    assert_eq!(default.plain_blocks, None);
    let (allocated, live) = plain.plain_blocks.expect("plain allocator counts");
    // Two uploads of glyphs (instances, boxes, coefficients, one frame block per frame
    // in flight: 5 blocks each) and the box indices: everything glyphcast made came
    // from it.
    let (uploads, indices) = (2 * (3 + 2), 1);
    assert!(allocated >= uploads + indices, "{allocated} blocks");
    assert_eq!(live, 0, "blocks not given back");
    let background = plain
        .rgba
        .chunks(4)
        .filter(|p| *p == &plain.rgba[..4])
        .count();
    assert!(background < plain.rgba.len() / 4 - 500, "glyphs are drawn");
    if differing(&plain.rgba, &default.rgba) > 0 {
        save("plain-memory", &plain.rgba);
        save("gpu-allocator", &default.rgba);
    }
    assert_eq!(differing(&plain.rgba, &default.rgba), 0);
    assert_eq!(plain.depth, default.depth);
}

/// A host allocator that reports blocks one byte short of the request.
struct ShortBlocks(Arc<PlainMemory>);

impl glyphcast::vk::MemoryAllocator for ShortBlocks {
    fn allocate(
        &self,
        request: &glyphcast::vk::MemoryRequest<'_>,
    ) -> glyphcast::Result<glyphcast::vk::MemoryBlock> {
        let mut block = self.0.allocate(request)?;
        block.size -= 1;
        Ok(block)
    }

    fn free(&self, block: glyphcast::vk::MemoryBlock) {
        self.0.free(block)
    }
}

/// A host allocator that breaks its contract (a block smaller than asked) is refused
/// with an error naming the allocation, before anything is bound to the block, and the
/// block is given back: no panic, no validation message.
#[test]
fn a_host_allocator_breaking_its_contract_is_refused() {
    let engine = Engine::new(Validation::On, true).expect("engine");
    let plain = Arc::new(PlainMemory::new(
        &engine.instance,
        engine.physical_device,
        engine.device.clone(),
    ));
    // SAFETY: as in `run_on`: the context and renderer are dropped before the engine.
    let context = unsafe {
        DeviceContext::with_memory(
            &engine.instance,
            engine.physical_device,
            engine.device.clone(),
            Arc::new(ShortBlocks(plain.clone())),
        )
    };
    let desc = RendererDesc {
        formats: TargetFormats {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            distance: None,
        },
        options: PassOptions::default(),
        frames_in_flight: 2,
        settings: RenderSettings::default(),
    };
    let error = match GlyphRenderer::new(&context, &desc) {
        Ok(_) => panic!("a short block was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(error.contains("proxy indices"), "{error}");
    assert!(
        error.contains("the memory allocator returned a block of"),
        "{error}"
    );
    drop(context);
    let (allocated, live) = plain.counts();
    assert_eq!((allocated, live), (1, 0));
    assert_eq!(engine.validation_messages(), Vec::<String>::new());
}

#[test]
fn unknown_options_and_bad_values_are_refused() {
    let args = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert!(
        parse(&args(&["--bogus"]))
            .unwrap_err()
            .contains("unknown option")
    );
    assert!(parse(&args(&["--samples", "3"])).is_err());
    assert!(parse(&args(&["--depth", "inverted"])).is_err());
    assert!(parse(&args(&["--frames"])).is_err());
    assert!(parse(&args(&["--allocator", "vma"])).is_err());
    let o = parse(&args(&[
        "--frames",
        "5",
        "--in-flight",
        "2",
        "--depth",
        "reversed",
        "--samples",
        "8",
        "--allocator",
        "plain",
        "--sync-validation",
        "--screenshot",
        "x.png",
    ]))
    .expect("valid options");
    assert_eq!((o.frames, o.in_flight, o.samples), (5, 2, 8));
    assert_eq!(o.depth, DepthConvention::Reversed);
    assert_eq!(o.validation, Validation::Sync);
    assert_eq!(o.allocator, MemorySource::Plain);
}

/// A render pass of the host's (Vulkan 1.0-1.2 style: colour and depth cleared and
/// stored by one subpass) instead of dynamic rendering: the same picture as the engine's
/// dynamic-rendering frame of that camera and those glyphs, under synchronization
/// validation.
#[test]
fn a_host_render_pass_draws_the_dynamic_rendering_picture() {
    let depth = DepthConvention::Standard;
    let dynamic = run(&Options {
        frames: 1,
        in_flight: 1,
        plane: false,
        ..options(depth, 1)
    })
    .expect("dynamic rendering run");
    let engine = Engine::new(Validation::Sync, true).expect("engine");
    let d = &engine.device;
    let render_pass = host_render_pass(d).expect("render pass");
    // SAFETY: as in `run_on`: the context and renderer are dropped before the engine.
    let context = unsafe {
        DeviceContext::new(
            &engine.instance,
            engine.physical_device,
            engine.device.clone(),
            engine.allocator(),
        )
    };
    let desc = RendererDesc {
        formats: TargetFormats {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            distance: None,
        },
        options: PassOptions {
            depth,
            render_pass,
            subpass: 0,
            ..PassOptions::default()
        },
        frames_in_flight: 1,
        settings: RenderSettings::default(),
    };
    let mut glyphs = GlyphRenderer::new(&context, &desc).expect("renderer");
    glyphs.set_glyphs(&dynamic.sets).expect("glyphs");
    // Settings replaced later are checked as at creation: a refused value names its
    // setting and leaves the renderer's own (the picture below is still the default's).
    let mut refused = RenderSettings::default();
    refused.lighting.ambient = 2.0;
    let err = glyphs.set_settings(&refused).expect_err("ambient 2");
    assert_eq!(err.setting_of(), Some(glyphcast::Setting::Ambient), "{err}");
    let (view, projection) = host_matrices(&camera(0), depth, extent().into());
    let view = HostView::whole(view, projection, WIDTH, HEIGHT);
    glyphs.set_view(0, &view).expect("view");
    let cmd = engine.command_buffers(1).expect("cmd")[0];
    let slot = Slot::new(&engine, cmd, (vk::SampleCountFlags::TYPE_1, DEPTH_FORMAT)).expect("slot");
    let views = [slot.color.view, slot.depth.view];
    let info = vk::FramebufferCreateInfo::default()
        .render_pass(render_pass)
        .attachments(&views)
        .width(WIDTH)
        .height(HEIGHT)
        .layers(1);
    // SAFETY: the views fit the render pass; destroyed below after the device is idle.
    let framebuffer = unsafe { d.create_framebuffer(&info, None) }.expect("framebuffer");
    let readback = engine
        .create_readback("colour", 4 * WIDTH as u64 * HEIGHT as u64)
        .expect("readback");
    let clear = [
        vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.55, 0.65, 0.8, 1.0],
            },
        },
        vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: depth.clear_depth(),
                stencil: 0,
            },
        },
    ];
    let begin_pass = vk::RenderPassBeginInfo::default()
        .render_pass(render_pass)
        .framebuffer(framebuffer)
        .render_area(extent().into())
        .clear_values(&clear);
    let copy = [vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(extent().into())];
    let to_transfer = [Attachment::Color.to_transfer(slot.color.image)];
    let host_read = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COPY)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)];
    // SAFETY: fresh command buffer; every handle lives until the device is idle.
    unsafe {
        d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())
            .expect("begin");
        d.cmd_begin_render_pass(cmd, &begin_pass, vk::SubpassContents::INLINE);
        glyphs.record(cmd, 0).expect("record");
        d.cmd_end_render_pass(cmd);
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_transfer),
        );
        let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        d.cmd_copy_image_to_buffer(cmd, slot.color.image, src, readback.buffer, &copy);
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&host_read),
        );
        d.end_command_buffer(cmd).expect("end");
        let cmds = [cmd];
        let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
        d.queue_submit(engine.queue, &submit, vk::Fence::null())
            .expect("submit");
        d.device_wait_idle().expect("wait");
    }
    let rgba = engine.read(&readback).expect("read").to_vec();
    if differing(&rgba, &dynamic.rgba) > 0 {
        save("render-pass", &rgba);
        save("dynamic-rendering", &dynamic.rgba);
    }
    assert_eq!(differing(&rgba, &dynamic.rgba), 0);
    engine.destroy_readback(readback).expect("free");
    // SAFETY: the device is idle.
    unsafe {
        d.destroy_framebuffer(framebuffer, None);
        d.destroy_render_pass(render_pass, None);
    }
    slot.destroy(&engine).expect("free");
    drop(glyphs);
    drop(context);
    assert_eq!(engine.validation_messages(), Vec::<String>::new());
    assert_eq!(dynamic.validation, Vec::<String>::new());
}

/// One subpass drawing colour and depth, both cleared; the colour stays in the
/// attachment layout for the copy that follows, made visible by the outgoing dependency.
fn host_render_pass(d: &ash::Device) -> Result<vk::RenderPass> {
    let attachment = |format, final_layout| {
        vk::AttachmentDescription::default()
            .format(format)
            .samples(vk::SampleCountFlags::TYPE_1)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
            .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
            .initial_layout(vk::ImageLayout::UNDEFINED)
            .final_layout(final_layout)
    };
    let attachments = [
        attachment(COLOR_FORMAT, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
        attachment(
            DEPTH_FORMAT,
            vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        ),
    ];
    let color = [vk::AttachmentReference {
        attachment: 0,
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    }];
    let depth = vk::AttachmentReference {
        attachment: 1,
        layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
    };
    let subpass = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&color)
        .depth_stencil_attachment(&depth)];
    let tests =
        vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
    let writes =
        vk::AccessFlags::COLOR_ATTACHMENT_WRITE | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE;
    let dependencies = [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | tests)
            .dst_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | tests)
            .dst_access_mask(writes | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ),
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
            .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags::TRANSFER)
            .dst_access_mask(vk::AccessFlags::TRANSFER_READ),
    ];
    let info = vk::RenderPassCreateInfo::default()
        .attachments(&attachments)
        .subpasses(&subpass)
        .dependencies(&dependencies);
    // SAFETY: a complete create info; the caller destroys the render pass.
    Ok(unsafe { d.create_render_pass(&info, None)? })
}
