//! The wgpu application on lavapipe through wgpu's Vulkan backend, under the validation
//! layer with synchronization validation, against glyphcast's own headless renderer of
//! the same glyphs and camera; `cargo test -p glyphcast-wgpu` runs these.
use super::*;
use frames::{Options, Run};
use glyphcast::{Gpu, GpuOptions, HeadlessRenderer, RenderSettings, RenderedImage};
use glyphcast_wgpu::{GlyphPass, GlyphPassDesc, GlyphTarget};
use scene::{HEIGHT, SQUARE, WIDTH};

/// glyphcast's headless render of frame `frame`'s camera, on its own validated device,
/// over the application's clear colour.
fn headless(frame: u32) -> RenderedImage {
    let gpu = Gpu::headless(&GpuOptions {
        validation: true,
        device: std::env::var("GLYPHCAST_DEVICE").ok(),
    })
    .expect("a Vulkan device with validation");
    let mut renderer = HeadlessRenderer::new(&gpu).expect("headless renderer");
    let c = scene::CLEAR_COLOR;
    let settings = RenderSettings {
        background: [c.r as f32, c.g as f32, c.b as f32, c.a as f32],
        ..RenderSettings::default()
    };
    let sets = scene::glyph_sets().expect("glyph sets");
    let camera = scene::camera(frame);
    let view = glyphcast::FrameView::new(&camera, WIDTH, HEIGHT);
    let image = renderer
        .render_view(&gpu, &sets, &view, &settings)
        .expect("headless render");
    assert_eq!(gpu.validation_errors(), Vec::<String>::new());
    image
}

/// The application's window depth back to the distance along each pixel's ray (NaN at
/// the cleared far end): eye depth e = P32 / (z + P22) for window depth z.
fn distances(run: &Run) -> Vec<f64> {
    let camera = scene::camera(run.last_frame);
    let p = scene::wgpu_camera(run.last_frame)
        .projection
        .to_cols_array_2d();
    let fwd = camera.frame().fwd;
    run.depth
        .iter()
        .enumerate()
        .map(|(k, &z)| {
            if z >= 1.0 {
                return f64::NAN;
            }
            let eye_depth = p[3][2] / (z as f64 + p[2][2]);
            let (i, j) = (k as u32 % WIDTH, k as u32 / WIDTH);
            eye_depth / camera.ray(i, j, WIDTH, HEIGHT).dir.dot(fwd)
        })
        .collect()
}

/// The glyphs' size, which depth errors are measured in.
fn glyph_scale() -> f64 {
    scene::glyph_sets()
        .expect("glyph sets")
        .iter()
        .flat_map(|s| &s.world)
        .map(|g| g.scale * g.bound)
        .fold(0.0, f64::max)
}

fn pixel(rgba: &[u8], k: usize) -> &[u8] {
    &rgba[4 * k..4 * k + 4]
}

fn save(name: &str, rgba: &[u8]) {
    let path = std::env::temp_dir().join(format!("wgpu_plane-{name}.png"));
    let _ = glyphcast::io::png::write_png_rgba8(&path, WIDTH, HEIGHT, rgba);
    eprintln!("image: {}", path.display());
}

/// Whether two pixels are the same colour. Exactly: the two pictures come from one shader,
/// one camera and one driver (the wgpu target's projection passes through y flipped and
/// back, which is exact in float64), and no pixel differs.
/// Whether pixel `k` has the reference's colour, each channel within one unit: the
/// application's camera is f32 matrices, which round the rays' directions (about 1e-7),
/// and with them the normals' last bits, against the reference's float64 camera.
fn same_colour(run: &Run, reference: &RenderedImage, k: usize) -> bool {
    pixel(&run.rgba, k)
        .iter()
        .zip(pixel(&reference.rgba, k))
        .all(|(a, b)| a.abs_diff(*b) <= 1)
}

/// The message of an error the call must return.
fn refusal<T>(result: glyphcast_wgpu::Result<T>) -> String {
    match result {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// How the glyphs of `run`'s last frame differ from glyphcast's headless render of its
/// camera, at every pixel.
#[derive(Debug)]
struct HeadlessMatch {
    covered: usize,
    coverage_differs: usize,
    /// The largest depth difference, in units of the glyph size.
    max_error: f64,
    colour_differs: usize,
}

fn match_headless(run: &Run, name: &str) -> HeadlessMatch {
    let reference = headless(run.last_frame);
    let wgpu = distances(run);
    let scale = glyph_scale();
    let mut m = HeadlessMatch {
        covered: 0,
        coverage_differs: 0,
        max_error: 0.0,
        colour_differs: 0,
    };
    for (k, &d) in wgpu.iter().enumerate() {
        let glyph = reference.distance[k] as f64;
        if d.is_nan() != glyph.is_nan() {
            m.coverage_differs += 1;
        } else if !d.is_nan() {
            m.covered += 1;
            m.max_error = m.max_error.max((d - glyph).abs() / scale);
            if !same_colour(run, &reference, k) {
                m.colour_differs += 1;
            }
        }
    }
    eprintln!("{name}: {m:?}");
    if m.coverage_differs + m.colour_differs > 0 {
        save(name, &run.rgba);
        save(&format!("{name}-headless"), &reference.rgba);
    }
    m
}

/// Thirty frames, three in flight, the camera moving every frame, no plane: no
/// validation message, and the last frame's glyphs where glyphcast's headless renderer
/// puts them, at every pixel: the same coverage, depth to 1e-4 of the glyph size, the
/// same colours (within one unit). The application gives the glyphs as arrays (`GlyphSet::from_arrays`)
/// and its camera as f32 matrices (`WgpuCamera::from_f32`); the reference draws them
/// from the scene, in float64.
#[test]
fn glyphs_match_glyphcasts_headless_render() {
    let options = Options {
        plane: false,
        ..Options::default()
    };
    let run = frames::run(&options).expect("headless run");
    eprintln!("adapter: {}", run.adapter);
    assert_eq!(run.validation, Vec::<String>::new());
    let m = match_headless(&run, "glyphs");
    assert!(m.covered > 1000, "{m:?}");
    assert_eq!(m.coverage_differs, 0, "{m:?}");
    assert!(m.max_error < 1e-4, "{m:?}");
    assert_eq!(m.colour_differs, 0, "{m:?}");
}

/// Three views per frame with one frame in flight (`encode_views`), each its own camera
/// and textures, twelve frames under synchronization validation: no message, and each
/// view's last frame matches the headless render of its own camera.
#[test]
fn several_views_per_frame_each_match_their_camera() {
    let options = Options {
        plane: false,
        frames: 12,
        in_flight: 1,
        views: 3,
        ..Options::default()
    };
    let run = frames::run(&options).expect("headless run");
    assert_eq!(run.validation, Vec::<String>::new());
    assert_eq!(run.views.len(), 3);
    for (v, view) in run.views.iter().enumerate() {
        let m = match_headless(view, &format!("view-{v}"));
        assert!(m.covered > 500, "view {v}: {m:?}");
        assert_eq!(m.coverage_differs, 0, "view {v}: {m:?}");
        assert!(m.max_error < 1e-4, "view {v}: {m:?}");
        assert_eq!(m.colour_differs, 0, "view {v}: {m:?}");
    }
    // The views are of different cameras.
    assert!(run.views[0].rgba != run.views[1].rgba && run.views[1].rgba != run.views[2].rgba);
}

/// Plane and glyph closer than this (units of the glyph size) are not judged: which one
/// a depth test keeps there depends on float32 depth rounding.
const CROSSING: f64 = 1e-3;

/// With the plane, each hides the other where it is in front: pixels where the
/// analytic plane lies in front of the glyph show the plane's depth and checkerboard,
/// pixels where the glyph lies in front show the glyph's depth and headless colour.
#[test]
fn the_plane_and_the_glyphs_hide_each_other() {
    let run = frames::run(&Options::default()).expect("headless run");
    assert_eq!(run.validation, Vec::<String>::new());
    let reference = headless(run.last_frame);
    let wgpu = distances(&run);
    let scale = glyph_scale();
    let camera = scene::camera(run.last_frame);
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let plane: Vec<f64> = (0..w * h)
        .map(|k| {
            let ray = camera.ray((k % w) as u32, (k / w) as u32, WIDTH, HEIGHT);
            SQUARE.hit(ray.origin, ray.dir).unwrap_or(f64::NAN)
        })
        .collect();
    let (mut plane_in_front, mut glyph_in_front, mut wrong) = (0, 0, Vec::new());
    for k in 0..w * h {
        let (x, y) = (k % w, k / w);
        // The plane's own edge is a rasterisation question, not an occlusion one.
        let edge = (y.saturating_sub(1)..=(y + 1).min(h - 1))
            .flat_map(|ny| (x.saturating_sub(1)..=(x + 1).min(w - 1)).map(move |nx| ny * w + nx))
            .any(|n| plane[n].is_nan() != plane[k].is_nan());
        let glyph = reference.distance[k] as f64;
        if edge
            || plane[k].is_nan()
            || glyph.is_nan()
            || (glyph - plane[k]).abs() < CROSSING * scale
        {
            continue;
        }
        let near = |d: f64, expected: f64| (d - expected).abs() < 1e-3 * scale;
        if plane[k] < glyph {
            // A glyph behind the plane: hidden.
            plane_in_front += 1;
            if !near(wgpu[k], plane[k]) || same_colour(&run, &reference, k) {
                wrong.push((x, y, "glyph seen through the plane"));
            }
        } else {
            // A glyph in front of the plane: it hides the plane.
            glyph_in_front += 1;
            if !near(wgpu[k], glyph) || !same_colour(&run, &reference, k) {
                wrong.push((x, y, "plane drawn over the glyph"));
            }
        }
    }
    eprintln!(
        "plane in front at {plane_in_front} glyph pixels, glyph in front at {glyph_in_front}; wrong: {wrong:?}"
    );
    if !wrong.is_empty() {
        save("plane", &run.rgba);
    }
    assert!(
        plane_in_front > 100 && glyph_in_front > 100,
        "{plane_in_front} {glyph_in_front}"
    );
    assert_eq!(wrong, Vec::new());
}

/// The largest difference of any channel between two RGBA pixels.
fn colour_gap(a: &[u8], b: &[u8]) -> u8 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// Multisampled: the scene and the glyphs draw into 4-sample textures (a ray cast through
/// every sample) resolved into the one-sample colour, under synchronization validation
/// with no message. Where the one-sample picture is flat (a pixel and its 8 neighbours
/// within `FLAT` of each other in colour, within 1% in depth, away from the image's
/// border: no silhouette, no
/// checkerboard edge, no crossing), the resolved picture is the one-sample one to within
/// `FLAT`; the pixels that differ more lie on edges, where samples mix, and there are
/// many of them.
#[test]
fn four_samples_resolve_into_the_one_sample_picture() {
    // Shading at 4 sample positions instead of the centre moves a colour where it changes
    // across the pixel; on a flat pixel by less than this (of 255).
    const FLAT: u8 = 12;
    let one = frames::run(&Options::default()).expect("one-sample run");
    let four = frames::run(&Options {
        samples: 4,
        ..Options::default()
    })
    .expect("four-sample run");
    assert_eq!(four.validation, Vec::<String>::new());
    let depth = distances(&one);
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let (mut flat, mut flat_differs, mut edges_differ) = (0, 0, 0);
    for k in 0..w * h {
        let (x, y) = (k % w, k / w);
        // A pixel on the image's border has neighbours it cannot see: not judged flat.
        let inside = x > 0 && y > 0 && x + 1 < w && y + 1 < h;
        let is_flat = inside
            && (y - 1..=y + 1)
                .flat_map(|ny| (x - 1..=x + 1).map(move |nx| ny * w + nx))
                .all(|n| {
                    let (a, b) = (depth[n], depth[k]);
                    let same_surface = (a.is_nan() && b.is_nan()) || (a - b).abs() < 0.01 * b.abs();
                    same_surface && colour_gap(pixel(&one.rgba, n), pixel(&one.rgba, k)) <= FLAT
                });
        let gap = colour_gap(pixel(&one.rgba, k), pixel(&four.rgba, k));
        if is_flat {
            flat += 1;
            if gap > FLAT {
                flat_differs += 1;
            }
        } else if gap > FLAT {
            edges_differ += 1;
        }
    }
    eprintln!(
        "{flat} flat pixels, {flat_differs} of them differ; {edges_differ} edge pixels differ"
    );
    if flat_differs > 0 {
        save("one-sample", &one.rgba);
        save("four-samples", &four.rgba);
    }
    assert!(flat > w * h / 3, "{flat}");
    assert_eq!(flat_differs, 0);
    assert!(
        edges_differ > 100,
        "the edges are not anti-aliased: {edges_differ}"
    );
}

/// Bad input is refused with an error that names it: another backend than Vulkan, no
/// frame in flight, the compute path, 3 samples, a texture of another format.
#[test]
// (wgpu 29's NoopBackendOptions has `enable` alone; wgpu 30's has more.)
#[allow(clippy::needless_update)]
fn wrong_backends_and_targets_are_refused() {
    let noop = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::NOOP,
        backend_options: wgpu::BackendOptions {
            noop: wgpu::NoopBackendOptions {
                enable: true,
                ..Default::default()
            },
            ..Default::default()
        },
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let adapter =
        glyphcast_wgpu::validation::block_on(noop.enumerate_adapters(wgpu::Backends::NOOP))
            .into_iter()
            .next()
            .expect("the noop adapter");
    let refused = refusal(glyphcast_wgpu::request_device(
        &adapter,
        &Default::default(),
    ));
    assert!(refused.contains("Vulkan backend"), "{refused}");
    let (device, _queue) =
        glyphcast_wgpu::validation::block_on(adapter.request_device(&Default::default()))
            .expect("a noop device");
    // SAFETY: refused before anything is drawn.
    let refused = refusal(unsafe { GlyphPass::new(&adapter, &device, &GlyphPassDesc::default()) });
    assert!(refused.contains("Noop"), "{refused}");

    let validated = glyphcast_wgpu::validation::ValidatedInstance::new(true).expect("instance");
    let adapter = validated.adapter().expect("adapter");
    {
        let (device, _queue) =
            glyphcast_wgpu::request_device(&adapter, &Default::default()).expect("device");
        let no_frames = GlyphPassDesc {
            frames_in_flight: 0,
            ..GlyphPassDesc::default()
        };
        // SAFETY: the device was made by `request_device`.
        let refused = refusal(unsafe { GlyphPass::new(&adapter, &device, &no_frames) });
        assert!(refused.contains("frame in flight"), "{refused}");
        let compute = GlyphPassDesc {
            settings: glyphcast::RenderSettings {
                path: glyphcast::RenderPath::Compute,
                ..glyphcast::RenderSettings::default()
            },
            ..GlyphPassDesc::default()
        };
        // SAFETY: as above.
        let refused = refusal(unsafe { GlyphPass::new(&adapter, &device, &compute) });
        assert!(
            refused.contains("records no compute-path dispatches"),
            "{refused}"
        );
        let bad_samples = GlyphPassDesc {
            samples: 3,
            ..GlyphPassDesc::default()
        };
        // SAFETY: as above.
        let refused = refusal(unsafe { GlyphPass::new(&adapter, &device, &bad_samples) });
        assert!(refused.contains("3 samples per pixel"), "{refused}");
        // SAFETY: as above.
        let mut glyphs =
            unsafe { GlyphPass::new(&adapter, &device, &GlyphPassDesc::default()) }.expect("pass");
        glyphs
            .set_glyphs(&scene::glyph_sets().expect("sets"))
            .expect("glyphs");
        let texture = |format| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: None,
                    size: wgpu::Extent3d {
                        width: 16,
                        height: 16,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let (bgra, depth) = (
            texture(wgpu::TextureFormat::Bgra8Unorm),
            texture(wgpu::TextureFormat::Depth32Float),
        );
        let target = GlyphTarget {
            color: &bgra,
            depth: &depth,
            resolve: None,
        };
        let refused = refusal(glyphs.encode(&scene::wgpu_camera(0), &target));
        assert!(refused.contains("Bgra8Unorm"), "{refused}");
    }
    assert_eq!(validated.messages(), Vec::<String>::new());
}
