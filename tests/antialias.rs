//! Anti-aliasing (`--samples 4|16`, issue 13): over a transparent background each
//! pixel's alpha is the fraction of its samples that glyphs cover, checked against the
//! float64 reference cast at the same sample positions (exactly, up to rounding) and
//! against the reference's coverage fraction over 8 x 8 rays per pixel (within a stated
//! tolerance); the depth map keeps one ray per pixel centre whatever the sample count.
use crate::common;
use glam::DVec3;
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::reference::reference_depth;
use glyphcast::io::npy::read_npy_f32;
use glyphcast::io::png::read_png_rgba8;
use glyphcast::render::RenderSettings;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::scene::Scene;

const SIZE: u32 = 64;

/// Three glyphs with thin and round lobes, seen obliquely: edges at every angle.
fn scene() -> Scene {
    let crossing = fibre_tensor(
        6,
        &[(direction(15.0, 10.0), 1.0), (direction(80.0, -20.0), 0.8)],
    );
    let single = fibre_tensor(4, &[(direction(-40.0, 35.0), 1.0)]);
    let sets = vec![
        glyph_set(
            symmetric(6),
            vec![DVec3::new(-0.6, 0.0, 0.0), DVec3::new(0.7, 0.4, 0.2)],
            0.8,
            vec![crossing.clone(), crossing],
        ),
        glyph_set(
            symmetric(4),
            vec![DVec3::new(0.1, -0.5, -0.3)],
            0.7,
            vec![single],
        ),
    ];
    glyphcast::accuracy::suite::scene(sets, DVec3::new(0.5, -4.0, 2.5), SIZE)
}

fn transparent(samples: u32) -> RenderSettings {
    RenderSettings {
        background: [0.0; 4],
        samples,
        ..Default::default()
    }
}

fn render(scene: &Scene, settings: &RenderSettings) -> RenderedImage {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let sets = prepare_scene(scene, 0.0).expect("preparing");
    let (w, h) = (scene.image.width, scene.image.height);
    renderer
        .render_view(
            &gpu,
            &sets,
            &glyphcast::FrameView::new(&scene.camera, w, h),
            settings,
        )
        .expect("rendering")
}

/// The fraction of each pixel's `k` x `k` sub-pixel rays (centres of a k-times finer
/// grid) that hit a glyph in float64.
fn reference_coverage(scene: &Scene, k: u32) -> Vec<f64> {
    let sets = prepare_scene(scene, 0.0).expect("preparing");
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    let (w, h) = (scene.image.width, scene.image.height);
    let fine = reference_depth(&world, &scene.camera, w * k, h * k);
    let mut coverage = vec![0.0; (w * h) as usize];
    for (n, depth) in fine.iter().enumerate() {
        let (x, y) = (n as u32 % (w * k), n as u32 / (w * k));
        if !depth.is_nan() {
            coverage[((y / k) * w + x / k) as usize] += 1.0 / (k * k) as f64;
        }
    }
    coverage
}

#[test]
fn supersampled_alpha_is_the_reference_coverage_fraction() {
    let scene = scene();
    let image = render(&scene, &transparent(16));
    glyphcast::io::png::write_png_rgba8(
        &common::output_dir().join("antialias-16.png"),
        SIZE,
        SIZE,
        &image.rgba,
    )
    .expect("PNG");
    let same_samples = reference_coverage(&scene, 4);
    let fine = reference_coverage(&scene, 8);
    let alpha: Vec<f64> = image
        .rgba
        .chunks_exact(4)
        .map(|p| p[3] as f64 / 255.0)
        .collect();
    let (mut edge, mut sum, mut worst, mut off_by_a_sample) = (0, 0.0, 0.0f64, 0);
    for n in 0..alpha.len() {
        // Alpha is 0 exactly where none of the pixel's 16 reference rays hits.
        assert_eq!(
            alpha[n] == 0.0,
            same_samples[n] == 0.0,
            "pixel {n}: {}",
            alpha[n]
        );
        // The same 16 sample rays: equal up to the 8-bit rounding, except where float32
        // and float64 disagree about one sample grazing an edge.
        let error = (alpha[n] - same_samples[n]).abs();
        let off = error > 0.5 / 255.0 + 1e-9;
        if off {
            off_by_a_sample += 1;
            assert!(
                error <= 1.0 / 16.0 + 0.5 / 255.0,
                "pixel {n}: {} vs {}",
                alpha[n],
                same_samples[n]
            );
        }
        let partial = |c: f64| c > 0.0 && c < 1.0;
        if partial(fine[n]) || partial(same_samples[n]) {
            edge += 1;
            let e = (alpha[n] - fine[n]).abs();
            sum += e;
            worst = worst.max(e);
        } else if !off {
            // Inside (or outside) for all 64 rays: inside (outside) for all 16 samples.
            assert_eq!(alpha[n], fine[n], "pixel {n}");
        }
    }
    let mean = sum / edge as f64;
    eprintln!(
        "{edge} edge pixels: |alpha - 64-ray coverage| mean {mean:.4}, max {worst:.4}; \
         {off_by_a_sample} pixels off by one of the 16 samples"
    );
    assert!(edge > 150, "{edge} edge pixels");
    assert!(off_by_a_sample <= 2, "{off_by_a_sample}");
    // A 4 x 4 grid estimates an area fraction: a straight edge between two rows of
    // samples is off by up to half a row (2/16 = 0.125); curved edges and corners a
    // little more. On average the estimate is unbiased and far closer.
    assert!(mean <= 0.04, "mean {mean}");
    assert!(worst <= 0.2, "max {worst}");
}

#[test]
fn four_samples_measure_quarters_and_one_sample_is_all_or_nothing() {
    let scene = scene();
    let four = render(&scene, &transparent(4));
    let one = render(&scene, &transparent(1));
    let quarters = reference_coverage(&scene, 2);
    let centres = reference_coverage(&scene, 1);
    let mut mismatched = 0;
    for n in 0..quarters.len() {
        let a4 = four.rgba[4 * n + 3];
        if a4 != (255.0 * quarters[n]).round() as u8 {
            mismatched += 1;
        }
        assert_eq!(one.rgba[4 * n + 3], (255.0 * centres[n]) as u8, "pixel {n}");
    }
    assert!(
        mismatched <= 2,
        "{mismatched} pixels off the reference quarters"
    );
}

#[test]
fn the_depth_map_is_the_pixel_centre_depth_at_any_sample_count() {
    let scene = scene();
    let bits = |image: &RenderedImage| -> Vec<u32> {
        image.distance.iter().map(|d| d.to_bits()).collect()
    };
    let one = bits(&render(&scene, &transparent(1)));
    assert_eq!(bits(&render(&scene, &transparent(4))), one);
    assert_eq!(bits(&render(&scene, &transparent(16))), one);
    // And through the command line, with an opaque background: alpha 255 everywhere.
    let dir = common::fresh_dir("antialias-cli");
    let json = dir.join("scene.json");
    std::fs::write(&json, scene.to_json()).expect("scene");
    let json = json.display().to_string();
    let run = |samples: &str| {
        let png = dir.join(format!("s{samples}.png")).display().to_string();
        let npy = dir.join(format!("s{samples}.npy")).display().to_string();
        let args = [
            "render",
            &json,
            "--samples",
            samples,
            "-o",
            &png,
            "--depth-out",
            &npy,
        ];
        let out = common::glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (_, _, rgba) = read_png_rgba8(std::path::Path::new(&png)).expect("PNG");
        let (_, depth) = read_npy_f32(std::path::Path::new(&npy)).expect("npy");
        (
            rgba,
            depth.iter().map(|d| d.to_bits()).collect::<Vec<u32>>(),
        )
    };
    let (_, depth1) = run("1");
    let (rgba16, depth16) = run("16");
    assert_eq!(depth16, depth1);
    assert!(rgba16.chunks_exact(4).all(|p| p[3] == 255));
}

#[test]
fn sample_counts_and_sizes_beyond_the_limit_are_usage_errors() {
    let dir = common::fresh_dir("antialias-errors");
    let json = dir.join("scene.json");
    std::fs::write(&json, scene().to_json()).expect("scene");
    let json = json.display().to_string();
    let png = dir.join("out.png").display().to_string();
    for (extra, words) in [
        (vec!["--samples", "8"], vec!["--samples", "1, 4 or 16"]),
        (
            vec!["--samples", "16", "--width", "5000", "--height", "10"],
            vec!["--samples 16", "20000", "16384"],
        ),
    ] {
        let mut args = vec!["render", &json, "-o", &png];
        args.extend(extra);
        let out = common::glyphcast(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for word in words {
            assert!(stderr.contains(word), "'{word}' not in {stderr}");
        }
        assert!(!std::path::Path::new(&png).exists());
    }
}
