//! The anatomical underlay (issue 13): its pixels against the volume resampled in
//! float64 at each pixel centre's point on the analytic plane, occlusion against the
//! float64 glyphs and the analytic plane (glyphs in front hide the plane, the plane
//! hides glyphs behind it), the percentile window, three planes with --slices, and the
//! errors of the command line.
use crate::common;
use common::underlay::{scalar_underlay, tensor_volume};
use glam::{DMat4, DQuat, DVec3};
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::reference::reference_depth;
use glyphcast::io::npy::read_npy_f32;
use glyphcast::io::png::read_png_rgba8;
use glyphcast::render::RenderSettings;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::{FrameView, HeadlessRenderer, RenderedImage};
use glyphcast::render::settings::parse_background;
use glyphcast::render::underlay::{Underlay, UnderlayPlane, UnderlayVolume};
use glyphcast::rng::SplitMix64;
use glyphcast::scene::{GlyphSet, ImageSize, Scene};
use glyphcast_dmri::volume::load_underlay;
use ndarray::{ArrayD, IxDyn};
use std::path::Path;
use std::sync::Arc;

/// The background of these renders (`--background black`).
const BACKGROUND: [u8; 3] = [0, 0, 0];

/// A `dims` volume of random values in [0, 100) (`channels` per voxel), a few of them NaN,
/// on a grid turned about an oblique axis, with voxel sizes (0.37, 0.29, 0.45), its
/// origin at `origin`.
fn random_volume(dims: [usize; 3], channels: usize, origin: DVec3, seed: u64) -> UnderlayVolume {
    let mut rng = SplitMix64::new(seed);
    let count = dims.iter().product::<usize>() * channels;
    let values: Vec<f32> = (0..count)
        .map(|n| {
            if n % 97 == 13 {
                f32::NAN
            } else {
                (100.0 * rng.unit()) as f32
            }
        })
        .collect();
    let rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.4);
    let affine =
        DMat4::from_scale_rotation_translation(DVec3::new(0.37, 0.29, 0.45), rotation, origin);
    UnderlayVolume::new("random", dims, channels, values, affine).expect("volume")
}

/// The sRGB bytes the PNG holds for windowed values g in [0, 1].
fn bytes(shade: [f64; 3]) -> [u8; 3] {
    shade.map(|g| (255.0 * g).round() as u8)
}

/// What a pixel of a plane-only view must show: the nearest plane's shade, if the ray
/// meets a plane where the volume has a value; `None` where the pixel centre lies within
/// `margin` (voxels) of the volume's edge or a plane's edge, where float32 may decide
/// either way. `Some(None)`: the background.
fn expected_plane_pixel(
    volume: &UnderlayVolume,
    planes: &[UnderlayPlane],
    ray: &glyphcast::camera::Ray,
) -> Option<Option<([u8; 3], f64)>> {
    let margin = 1e-3;
    let mut hits: Vec<(f64, &UnderlayPlane)> = planes
        .iter()
        .filter_map(|p| p.intersect(ray).map(|t| (t, p)))
        .collect();
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Near a plane's edge (in its own s, t) the rasteriser may go either way.
    for plane in planes {
        let shrunk = UnderlayPlane {
            origin: plane.origin + margin * (plane.u + plane.v),
            u: plane.u * (1.0 - 2.0 * margin),
            v: plane.v * (1.0 - 2.0 * margin),
            sample_offset: DVec3::ZERO,
        };
        let grown = UnderlayPlane {
            origin: plane.origin - margin * (plane.u + plane.v),
            u: plane.u * (1.0 + 2.0 * margin),
            v: plane.v * (1.0 + 2.0 * margin),
            sample_offset: DVec3::ZERO,
        };
        if shrunk.intersect(ray).is_some() != grown.intersect(ray).is_some() {
            return None;
        }
    }
    for (t, plane) in hits {
        // The volume is sampled on the slice the plane was moved off.
        let point = ray.origin + t * ray.dir - plane.sample_offset;
        let p = volume.voxel_of(point).to_array();
        let near_edge = (0..3).any(|a| {
            let edge = volume.dims[a] as f64 - 0.5;
            (p[a] + 0.5).abs() < margin || (p[a] - edge).abs() < margin
        });
        // Where the cell around the point changes (a NaN voxel's neighbourhood begins),
        // float32 may also go either way.
        let shade = volume.shade(point);
        let steps = [DVec3::X, DVec3::Y, DVec3::Z].map(|d| 1e-3 * d);
        let ambiguous = steps.iter().any(|&d| {
            volume.shade(point + d).is_some() != shade.is_some()
                || volume.shade(point - d).is_some() != shade.is_some()
        });
        if near_edge || ambiguous {
            return None;
        }
        match shade {
            Some(shade) => return Some(Some((bytes(shade), t))),
            // NaN around this point: the plane is not drawn here; a farther plane may be.
            None => continue,
        }
    }
    Some(None)
}

/// Compares every pixel where no glyph is seen (distance NaN) with the planes' expected
/// colour; returns the number of underlay pixels compared.
fn check_plane_pixels(image: &RenderedImage, camera: &Camera, underlay: &Underlay) -> usize {
    let (w, h) = (image.width, image.height);
    let (mut compared, mut worst) = (0, 0u8);
    for j in 0..h {
        for i in 0..w {
            let n = (j * w + i) as usize;
            if !image.distance[n].is_nan() {
                continue;
            }
            let ray = camera.ray(i, j, w, h);
            let Some(expected) = expected_plane_pixel(&underlay.volume, &underlay.planes, &ray)
            else {
                continue;
            };
            let got = &image.rgba[4 * n..4 * n + 4];
            let want = expected.map_or(BACKGROUND, |(rgb, _)| rgb);
            let diff = (0..3).map(|c| got[c].abs_diff(want[c])).max().unwrap_or(0);
            worst = worst.max(diff);
            // One level: the GPU samples in float32 and encodes sRGB in hardware.
            assert!(
                diff <= 1,
                "pixel ({i}, {j}): {got:?}, expected {want:?} ({})",
                if expected.is_some() {
                    "underlay"
                } else {
                    "background"
                }
            );
            compared += usize::from(expected.is_some());
        }
    }
    eprintln!("{compared} underlay pixels, largest difference {worst} levels");
    compared
}

fn settings() -> RenderSettings {
    RenderSettings {
        background: parse_background("black").expect("black"),
        ..Default::default()
    }
}

/// One small glyph at `center`, scale `scale`: a crossing of two fibres, order 4.
fn glyph(center: DVec3, scale: f64) -> GlyphSet {
    let coeffs = fibre_tensor(
        4,
        &[(direction(20.0, 10.0), 1.0), (direction(110.0, -5.0), 0.7)],
    );
    glyph_set(symmetric(4), vec![center], scale, vec![coeffs])
}

fn perspective(eye: DVec3, size: u32) -> (Camera, ImageSize) {
    (
        Camera {
            projection: Projection::Perspective { fov_y_deg: 35.0 },
            eye,
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        ImageSize {
            width: size,
            height: size,
        },
    )
}

/// The plane z = `z` over [-1.5, 1.5]^2.
fn square(z: f64) -> UnderlayPlane {
    UnderlayPlane {
        origin: DVec3::new(-1.5, -1.5, z),
        u: DVec3::new(3.0, 0.0, 0.0),
        v: DVec3::new(0.0, 3.0, 0.0),
        sample_offset: DVec3::ZERO,
    }
}

fn render(scene: &Scene, underlay: Option<&Underlay>) -> (RenderedImage, Vec<f64>) {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let sets = prepare_scene(scene, 0.0).expect("preparing");
    let (w, h) = (scene.image.width, scene.image.height);
    let image = renderer
        .render_view(
            &gpu,
            &sets,
            &FrameView::new(&scene.camera, w, h).with_underlay(underlay),
            &settings(),
        )
        .expect("rendering");
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    (image, reference_depth(&world, &scene.camera, w, h))
}

fn save(name: &str, image: &RenderedImage) {
    let path = common::output_dir().join(format!("underlay-{name}.png"));
    glyphcast::io::png::write_png_rgba8(&path, image.width, image.height, &image.rgba)
        .expect("writing the PNG");
}

/// A scalar and an RGB volume on an oblique, anisotropic grid that covers part of an
/// oblique view of the plane: every pixel where no glyph is seen shows the volume
/// resampled trilinearly at the pixel centre's plane point, or the background outside
/// the volume and around NaN voxels.
#[test]
fn underlay_pixels_equal_the_volume_resampled_at_the_plane() {
    for channels in [1, 3] {
        let volume = random_volume([9, 8, 7], channels, DVec3::new(-1.2, -0.9, -1.3), 7);
        let underlay = Underlay {
            volume: Arc::new(volume),
            planes: vec![square(0.1)],
        };
        let (camera, image) = perspective(DVec3::new(1.5, -3.0, 4.5), 128);
        let scene = Scene {
            glyph_sets: vec![glyph(DVec3::new(1.2, 1.2, 0.3), 0.2)],
            camera,
            image,
        };
        let (rendered, _) = render(&scene, Some(&underlay));
        save(&format!("resampled-{channels}"), &rendered);
        let compared = check_plane_pixels(&rendered, &scene.camera, &underlay);
        assert!(compared > 3000, "{compared} underlay pixels");
    }
}

/// Glyphs in front of the plane, behind it, and cut by it: wherever the float64 glyph
/// hit is nearer than the analytic plane the glyph is seen (the same depth as without
/// the plane), and wherever the plane is nearer the underlay is seen and the depth map
/// holds NaN; a glyph behind the plane that shows without the underlay is hidden by it.
#[test]
fn glyphs_and_the_plane_occlude_each_other() {
    let volume = random_volume([12, 12, 8], 1, DVec3::new(-2.0, -1.8, -1.5), 11);
    let underlay = Underlay {
        volume: Arc::new(volume),
        planes: vec![square(0.0)],
    };
    let (camera, image) = perspective(DVec3::new(0.8, -2.5, 4.0), 128);
    let scene = Scene {
        glyph_sets: vec![
            glyph(DVec3::new(-0.6, 0.0, 0.45), 0.4),
            glyph(DVec3::new(0.6, 0.0, -0.45), 0.4),
            glyph(DVec3::new(0.0, 0.7, 0.0), 0.45),
        ],
        camera,
        image,
    };
    let (alone, reference) = render(&scene, None);
    let (with_plane, _) = render(&scene, Some(&underlay));
    save("occlusion", &with_plane);
    let (w, h) = (scene.image.width, scene.image.height);
    let plane = &underlay.planes[0];
    let (mut in_front, mut hidden, mut plane_seen) = (0, 0, 0);
    for j in 0..h {
        for i in 0..w {
            let n = (j * w + i) as usize;
            let ray = scene.camera.ray(i, j, w, h);
            let t_plane = plane
                .intersect(&ray)
                .filter(|&t| underlay.volume.sample(ray.origin + t * ray.dir).is_some());
            let t_glyph = reference[n];
            let got = with_plane.distance[n];
            match (t_glyph.is_nan(), t_plane) {
                (false, Some(t)) if (t_glyph - t).abs() < 1e-3 * t => {} // a tie: either
                (false, Some(t)) if t_glyph < t => {
                    in_front += 1;
                    assert_eq!(got.to_bits(), alone.distance[n].to_bits(), "({i}, {j})");
                }
                (false, None) => {
                    assert_eq!(got.to_bits(), alone.distance[n].to_bits(), "({i}, {j})");
                }
                (_, Some(_)) => {
                    plane_seen += 1;
                    if !t_glyph.is_nan() && !alone.distance[n].is_nan() {
                        hidden += 1;
                    }
                    assert!(
                        got.is_nan(),
                        "({i}, {j}): a glyph at {got} seen through the plane"
                    );
                }
                (true, None) => assert!(got.is_nan(), "({i}, {j}): {got}"),
            }
        }
    }
    eprintln!("{in_front} glyph pixels in front, {hidden} hidden, {plane_seen} plane pixels");
    assert!(in_front > 300 && hidden > 300 && plane_seen > 3000);
    // And where the plane is seen, it has the resampled colour.
    check_plane_pixels(&with_plane, &scene.camera, &underlay);
}

// ---- The command line: NIfTI files, slices and errors.

/// The nearest-rank percentile of the finite values, computed here on its own.
fn percentile(values: &[f64], p: f64) -> f64 {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    let rank = ((p / 100.0 * sorted.len() as f64).ceil() as usize).max(1);
    sorted[rank - 1]
}

/// Runs `glyphcast render ARGS -o out.png --depth-out out.npy --save-scene out.json`;
/// returns the image (as a RenderedImage) and the scene.
fn render_cli(dir: &Path, args: &[&str]) -> (RenderedImage, Scene) {
    let png = dir.join("out.png").display().to_string();
    let npy = dir.join("out.npy").display().to_string();
    let json = dir.join("out.json").display().to_string();
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", &png, "--depth-out", &npy, "--save-scene", &json]);
    let run = common::glyphcast(&all);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{all:?}:\n{stderr}");
    let (width, height, rgba) = read_png_rgba8(Path::new(&png)).expect("PNG");
    let (_, distance) = read_npy_f32(Path::new(&npy)).expect("depth");
    let scene = Scene::load(Path::new(&json)).expect("scene");
    let image = RenderedImage {
        width,
        height,
        rgba,
        distance,
        draws: 0,
        gpu_ms: None,
        mesh: None,
        path: glyphcast::RenderPath::Fragment,
        passes: 1,
        culling: glyphcast::render::Culling::Off,
    };
    (image, scene)
}

/// `--underlay` on the middle axial slice with `--underlay-plane centre`: the plane
/// through the slice's voxel centres (z = -3 + 2 * 2 = 1), over the slice's voxel
/// edges; the default window is the 2nd to 98th percentile, `--underlay-range` replaces
/// it.
#[test]
fn the_command_line_draws_the_underlay_on_the_slice() {
    let dir = common::fresh_dir("underlay-cli");
    let (tensors, _) = tensor_volume(&dir);
    let fa = scalar_underlay(&dir, "fa.nii");
    let (mut volume, _) = load_underlay(Path::new(&fa)).expect("underlay");
    let values: Vec<f64> = volume.values().iter().map(|&v| v as f64).collect();
    let window = (percentile(&values, 2.0), percentile(&values, 98.0));
    assert_eq!(volume.window(), window);
    let plane = UnderlayPlane {
        origin: DVec3::new(-6.0, -5.0, 1.0),
        u: DVec3::new(12.0, 0.0, 0.0),
        v: DVec3::new(0.0, 10.0, 0.0),
        sample_offset: DVec3::ZERO,
    };
    let base = [
        "--tensor",
        &tensors,
        "--order",
        "2",
        "--underlay",
        &fa,
        "--underlay-plane",
        "centre",
        "--width",
        "120",
        "--height",
        "100",
        "--background",
        "black",
    ];
    let (image, scene) = render_cli(&dir, &base);
    glyphcast::io::png::write_png_rgba8(
        &common::output_dir().join("underlay-cli.png"),
        image.width,
        image.height,
        &image.rgba,
    )
    .expect("copy");
    let underlay = Underlay {
        volume: Arc::new(volume.clone()),
        planes: vec![plane],
    };
    let compared = check_plane_pixels(&image, &scene.camera, &underlay);
    assert!(compared > 1000, "{compared}");
    let mut args = base.to_vec();
    args.extend_from_slice(&["--underlay-range", "30:60"]);
    let (image, scene) = render_cli(&dir, &args);
    volume.set_window(30.0, 60.0).expect("window");
    let underlay = Underlay {
        volume: Arc::new(volume),
        planes: vec![plane],
    };
    assert!(check_plane_pixels(&image, &scene.camera, &underlay) > 1000);
}

/// With --slices and `--underlay-plane centre`, three planes: sagittal, coronal and
/// axial through the voxel centres of the chosen indices, each over its slice's extent;
/// each pixel shows the nearest.
#[test]
fn three_slices_draw_three_planes() {
    let dir = common::fresh_dir("underlay-slices");
    let (tensors, _) = tensor_volume(&dir);
    let fa = scalar_underlay(&dir, "fa.nii");
    let (volume, _) = load_underlay(Path::new(&fa)).expect("underlay");
    let (image, scene) = render_cli(
        &dir,
        &[
            "--tensor",
            &tensors,
            "--order",
            "2",
            "--underlay",
            &fa,
            "--underlay-plane",
            "centre",
            "--slices",
            "2,3,1",
            "--width",
            "128",
            "--height",
            "128",
            "--background",
            "black",
        ],
    );
    glyphcast::io::png::write_png_rgba8(
        &common::output_dir().join("underlay-slices.png"),
        image.width,
        image.height,
        &image.rgba,
    )
    .expect("copy");
    // Voxel edges: x from -6 to 6, y from -5 to 5, z from -4 to 4; slices at
    // x = -5 + 2 * 2 = -1, y = -4 + 3 * 2 = 2, z = -3 + 1 * 2 = -1.
    let planes = vec![
        UnderlayPlane {
            origin: DVec3::new(-1.0, -5.0, -4.0),
            u: DVec3::new(0.0, 10.0, 0.0),
            v: DVec3::new(0.0, 0.0, 8.0),
            sample_offset: DVec3::ZERO,
        },
        UnderlayPlane {
            origin: DVec3::new(-6.0, 2.0, -4.0),
            u: DVec3::new(12.0, 0.0, 0.0),
            v: DVec3::new(0.0, 0.0, 8.0),
            sample_offset: DVec3::ZERO,
        },
        UnderlayPlane {
            origin: DVec3::new(-6.0, -5.0, -1.0),
            u: DVec3::new(12.0, 0.0, 0.0),
            v: DVec3::new(0.0, 10.0, 0.0),
            sample_offset: DVec3::ZERO,
        },
    ];
    let underlay = Underlay {
        volume: Arc::new(volume),
        planes,
    };
    let compared = check_plane_pixels(&image, &scene.camera, &underlay);
    assert!(compared > 1500, "{compared}");
}

/// By default the underlay lies behind the glyphs: the plane of the slice moved away
/// from the camera by the largest glyph's radius (the default scale, 0.45 of the 2 mm
/// voxels) and 2 % more, where it shows the volume on the slice itself (sampled where
/// the plane was before it moved), as the float64 plane does; every
/// glyph pixel of the render without underlay is a glyph pixel with it, at the same
/// depth, where the plane through the centres hides some (the far halves).
#[test]
fn the_underlay_lies_behind_the_glyphs() {
    let dir = common::fresh_dir("underlay-behind");
    let (tensors, _) = tensor_volume(&dir);
    let fa = scalar_underlay(&dir, "fa.nii");
    let (volume, _) = load_underlay(Path::new(&fa)).expect("underlay");
    let base = [
        "--tensor",
        &tensors,
        "--order",
        "2",
        "--width",
        "120",
        "--height",
        "100",
        "--background",
        "black",
    ];
    let (bare, _) = render_cli(&dir, &base);
    let mut behind_args = base.to_vec();
    behind_args.extend_from_slice(&["--underlay", &fa]);
    let (behind, scene) = render_cli(&dir, &behind_args);
    let mut centre_args = behind_args.clone();
    centre_args.extend_from_slice(&["--underlay-plane", "centre"]);
    let (centre, _) = render_cli(&dir, &centre_args);
    save("behind", &behind);
    let glyph_pixels: Vec<usize> = (0..bare.distance.len())
        .filter(|&n| bare.distance[n].is_finite())
        .collect();
    assert!(glyph_pixels.len() > 500, "{}", glyph_pixels.len());
    for &n in &glyph_pixels {
        let (a, b) = (bare.distance[n], behind.distance[n]);
        assert!(
            b.is_finite() && (a - b).abs() <= 1e-4 * a.abs().max(1.0),
            "pixel {n}: glyph at {a} without the underlay, {b} with it"
        );
    }
    let hidden = glyph_pixels
        .iter()
        .filter(|&&n| !centre.distance[n].is_finite())
        .count();
    assert!(hidden > 50, "the centre plane hides far halves: {hidden}");
    // The plane itself: the slice z = 1 moved away from the camera.
    let away = (scene.camera.target - scene.camera.eye).z.signum();
    let plane = UnderlayPlane {
        origin: DVec3::new(-6.0, -5.0, 1.0 + away * 0.9 * 1.02),
        u: DVec3::new(12.0, 0.0, 0.0),
        v: DVec3::new(0.0, 10.0, 0.0),
        sample_offset: DVec3::new(0.0, 0.0, away * 0.9 * 1.02),
    };
    let underlay = Underlay {
        volume: Arc::new(volume),
        planes: vec![plane],
    };
    assert!(check_plane_pixels(&behind, &scene.camera, &underlay) > 1000);
}

/// Exits with `code`, one error line holding each of `words`, no output written.
fn expect_exit(code: i32, args: &[&str], dir: &Path, words: &[&str]) {
    let png = dir.join("fail.png").display().to_string();
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", &png]);
    let run = common::glyphcast(&all);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(code), "{all:?}:\n{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("error:"))
        .unwrap_or_else(|| panic!("no error line:\n{stderr}"));
    for word in words {
        assert!(line.contains(word), "'{word}' not in: {line}");
    }
    assert!(!Path::new(&png).exists(), "output written");
}

#[test]
fn underlay_errors_name_the_file_and_the_field() {
    let dir = common::fresh_dir("underlay-errors");
    let inputs = common::fresh_dir("underlay-errors-in");
    let (tensors, _) = tensor_volume(&inputs);
    let volume = ["--tensor", tensors.as_str(), "--order", "2"];
    let with = |extra: &[&str]| -> Vec<String> {
        volume.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |code: i32, extra: &[&str], words: &[&str]| {
        let args = with(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        expect_exit(code, &args, &dir, words);
    };
    let missing = inputs.join("missing.nii").display().to_string();
    run(1, &["--underlay", &missing], &["missing.nii"]);
    // A 4D image that is not RGB.
    let four = inputs.join("four.nii");
    common::write_nifti(&four, &ArrayD::zeros(IxDyn(&[4, 4, 4, 2])), DMat4::IDENTITY);
    let four = four.display().to_string();
    run(1, &["--underlay", &four], &["four.nii", "dim", "4x4x4x2"]);
    // No sform or qform: no place in world space.
    let header = glyphcast_dmri::io::nifti::NiftiHeader {
        pixdim: [1.0; 8],
        ..Default::default()
    };
    let data = ArrayD::<f64>::from_elem(IxDyn(&[4, 4, 4]), 1.0);
    let bytes = glyphcast_dmri::io::nifti::write::nifti1_bytes(&header, data.view(), false, "bare")
        .expect("encoding");
    let bare = inputs.join("bare.nii");
    std::fs::write(&bare, bytes).expect("writing");
    let bare = bare.display().to_string();
    run(1, &["--underlay", &bare], &["bare.nii", "sform"]);
    // An affine that puts the underlay far from the slice.
    let far = inputs.join("far.nii");
    let away = DMat4::from_translation(DVec3::new(500.0, 0.0, 0.0));
    common::write_nifti(&far, &ArrayD::from_elem(IxDyn(&[4, 4, 4]), 1.0), away);
    let far = far.display().to_string();
    run(
        1,
        &["--underlay", &far],
        &["far.nii", "affine", "does not reach"],
    );
    // Usage errors: the window, the flag's company.
    let fa = scalar_underlay(&inputs, "fa.nii");
    run(
        2,
        &["--underlay", &fa, "--underlay-range", "nan:1"],
        &["--underlay-range"],
    );
    run(
        2,
        &["--underlay", &fa, "--underlay-range", "5:1"],
        &["--underlay-range"],
    );
    run(2, &["--underlay-range", "0:1"], &["--underlay"]);
    run(
        2,
        &["--underlay-plane", "back"],
        &["--underlay-plane", "--underlay"],
    );
    run(
        2,
        &["--underlay", &fa, "--underlay-plane", "middle"],
        &["--underlay-plane", "back", "centre"],
    );
    let scene = inputs.join("scene.json");
    let (camera, image) = perspective(DVec3::new(0.0, -3.0, 3.0), 32);
    let one = Scene {
        glyph_sets: vec![glyph(DVec3::ZERO, 0.5)],
        camera,
        image,
    };
    std::fs::write(&scene, one.to_json()).expect("scene");
    let args = [scene.display().to_string(), "--underlay".into(), fa.clone()];
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    expect_exit(2, &args, &dir, &["--underlay", "volume"]);
}

/// An RGB underlay [x, y, z, 3] read from a NIfTI file keeps each voxel's three values
/// together and in order, and its affine: at a voxel centre the sample is that voxel's
/// (i + 10 j + 100 k + 1000 c for channel c), up to the float32 rounding of the sform,
/// which moves the centre by ~1e-7 voxels; a wrong interleaving is off by 1 or more.
#[test]
fn an_rgb_file_is_read_voxel_by_voxel_with_its_affine() {
    let dir = common::fresh_dir("underlay-rgb");
    let dims = [4, 3, 2];
    let mut data = ArrayD::<f64>::zeros(IxDyn(&[dims[0], dims[1], dims[2], 3]));
    for ((i, j, k, c), v) in data
        .indexed_iter_mut()
        .map(|(ix, v)| ((ix[0], ix[1], ix[2], ix[3]), v))
    {
        *v = (i + 10 * j + 100 * k + 1000 * c) as f64;
    }
    let affine = DMat4::from_scale_rotation_translation(
        DVec3::new(1.5, 2.0, 2.5),
        DQuat::from_rotation_x(0.3),
        DVec3::new(4.0, -2.0, 1.0),
    );
    let path = dir.join("rgb.nii");
    common::write_nifti(&path, &data, affine);
    let (volume, _) = load_underlay(&path).expect("RGB underlay");
    assert_eq!((volume.dims, volume.channels), (dims, 3));
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let world = affine.transform_point3(DVec3::new(i as f64, j as f64, k as f64));
                let got = volume.sample(world).expect("inside");
                for (c, value) in got.iter().enumerate() {
                    let want = (i + 10 * j + 100 * k + 1000 * c) as f64;
                    assert!(
                        (value - want).abs() < 1e-3,
                        "({i}, {j}, {k}) channel {c}: {value}"
                    );
                }
            }
        }
    }
}
