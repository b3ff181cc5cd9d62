//! Figure options (issue 13): `--negative` replacing a scene's mode, sign colouring
//! checked against the sign of f at the float64 reference's hit points, backgrounds
//! (transparent where the reference sees no glyph, named and hex colours written as the
//! exact 8-bit values), and magnitude colouring whose default range ends at the largest
//! glyph radius drawn.
use crate::common;
use glam::DVec3;
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::NegativeMode;
use glyphcast::glyph::bounds::sampled_max_radius;
use glyphcast::io::npy::read_npy_f32;
use glyphcast::io::png::read_png_rgba8;
use glyphcast::render::frame::SceneExtent;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::settings::{SIGN_COLORS, parse_background};
use glyphcast::render::{ColorMode, Method, RenderPath, RenderSettings};
use glyphcast::scene::{GlyphSet, Scene};
use std::path::Path;

/// The test scenes' framing: the accuracy suite's, at 128 x 128.
fn scene(sets: Vec<GlyphSet>, eye: DVec3) -> Scene {
    glyphcast::accuracy::suite::scene(sets, eye, 128)
}

/// One glyph with a positive pair of lobes and a negative pair (weight 0.8).
fn signed_scene(negative: NegativeMode) -> Scene {
    let pos = fibre_tensor(4, &[(direction(10.0, 15.0), 1.0)]);
    let neg = fibre_tensor(4, &[(direction(100.0, -10.0), 0.8)]);
    let coeffs: Vec<f64> = pos.iter().zip(&neg).map(|(p, n)| p - n).collect();
    let mut set = glyph_set(symmetric(4), vec![DVec3::ZERO], 1.0, vec![coeffs]);
    set.negative = negative;
    scene(vec![set], DVec3::new(0.4, -0.6, 4.0))
}

/// Renders `scene` and checks its depth against the reference: no holes, no false hits.
fn render_exactly(scene: &Scene, settings: &RenderSettings) -> common::Rendered {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let r = common::render_and_compare(&gpu, &mut renderer, scene, settings);
    let c = r.comparison;
    if c.holes != 0 || c.false_hits != 0 || c.covered < 300 {
        common::save_failure_images("figures", &r);
        panic!("{c}");
    }
    r
}

fn write_scene(dir: &Path, name: &str, scene: &Scene) -> String {
    let path = dir.join(name);
    std::fs::write(&path, scene.to_json()).expect("writing the scene");
    path.display().to_string()
}

/// Runs `glyphcast render` and returns its PNG's pixels and its depth map.
fn render_cli(args: &[&str], dir: &Path, name: &str) -> (Vec<u8>, Vec<f32>) {
    let png = dir.join(format!("{name}.png"));
    let npy = dir.join(format!("{name}.npy"));
    let (png_arg, npy_arg) = (png.display().to_string(), npy.display().to_string());
    let mut all = vec!["render"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", &png_arg, "--depth-out", &npy_arg]);
    let run = common::glyphcast(&all);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{all:?}:\n{stderr}");
    let (_, _, rgba) = read_png_rgba8(&png).expect("reading the PNG");
    let (_, depth) = read_npy_f32(&npy).expect("reading the depth map");
    (rgba, depth)
}

#[test]
fn negative_flag_hides_as_the_scene_file_does() {
    let dir = common::fresh_dir("figures-negative");
    let abs = write_scene(&dir, "abs.json", &signed_scene(NegativeMode::Abs));
    let hide = write_scene(&dir, "hide.json", &signed_scene(NegativeMode::Hide));
    let (_, from_file) = render_cli(&[&hide], &dir, "file");
    let (_, from_flag) = render_cli(&[&abs, "--negative", "hide"], &dir, "flag");
    let (_, abs_depth) = render_cli(&[&abs], &dir, "abs");
    let (_, back_to_abs) = render_cli(&[&hide, "--negative", "abs"], &dir, "back");
    let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&from_flag), bits(&from_file), "--negative hide");
    assert_eq!(bits(&back_to_abs), bits(&abs_depth), "--negative abs");
    let covered = |d: &[f32]| d.iter().filter(|v| !v.is_nan()).count();
    let (h, a) = (covered(&from_flag), covered(&abs_depth));
    assert!(h * 10 < a * 8, "hide covers {h} px, abs {a} px");
    // The hidden image itself matches the float64 reference of the hide scene.
    render_exactly(
        &signed_scene(NegativeMode::Hide),
        &RenderSettings::default(),
    );
    let run = common::glyphcast(&["render", &abs, "--negative", "half"]);
    assert_eq!(
        run.status.code(),
        Some(2),
        "a bad --negative is a usage error"
    );
}

/// The sign of f at each pixel's float64 hit point (None for a miss or where |f| is
/// within `margin` of zero, where float32 may land on either side of the lobe's edge).
fn reference_signs(scene: &Scene, r: &common::Rendered, margin: f64) -> Vec<Option<bool>> {
    let glyph = &r.sets[0].world[0];
    let (w, h) = (scene.image.width, scene.image.height);
    (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .zip(&r.reference)
        .map(|((i, j), &t)| {
            let ray = scene.camera.ray(i, j, w, h);
            let q = (ray.origin + t * ray.dir - glyph.center) / glyph.scale;
            let f = glyph.poly.eval(q.normalize());
            (t.is_finite() && f.abs() > margin).then_some(f > 0.0)
        })
        .collect()
}

#[test]
fn sign_colouring_follows_the_sign_of_f_at_the_reference_hits() {
    let color: ColorMode = "sign".parse().expect("sign");
    assert_eq!(
        color,
        ColorMode::Sign {
            positive: SIGN_COLORS.0,
            negative: SIGN_COLORS.1
        }
    );
    let exact = RenderSettings {
        color,
        ..Default::default()
    };
    let compute = RenderSettings {
        path: RenderPath::Compute,
        ..exact
    };
    let affine = RenderSettings {
        method: Method::Affine,
        ..exact
    };
    for (name, settings) in [("exact", exact), ("compute", compute), ("affine", affine)] {
        for negative in [NegativeMode::Abs, NegativeMode::Hide] {
            let scene = signed_scene(negative);
            let r = render_exactly(&scene, &settings);
            let (mut red, mut blue) = (0, 0);
            for (pixel, sign) in r
                .image
                .rgba
                .chunks_exact(4)
                .zip(reference_signs(&scene, &r, 0.02))
            {
                let (rr, b) = (pixel[0] as i32, pixel[2] as i32);
                match sign {
                    Some(true) => {
                        assert!(rr >= b + 16, "{name} {negative:?}: f > 0 but {pixel:?}");
                        red += 1;
                    }
                    Some(false) => {
                        assert!(b >= rr + 16, "{name} {negative:?}: f < 0 but {pixel:?}");
                        blue += 1;
                    }
                    None => {}
                }
            }
            eprintln!("{name} {negative:?}: {red} red, {blue} blue pixels");
            assert!(red > 300, "{name} {negative:?}: {red} positive pixels");
            match negative {
                NegativeMode::Abs => assert!(blue > 300, "{name}: {blue} negative pixels"),
                NegativeMode::Hide => assert_eq!(blue, 0, "{name}: hidden lobes drawn"),
            }
        }
    }
    let mesh = RenderSettings {
        method: "mesh:3".parse().expect("mesh"),
        ..exact
    };
    let error = mesh.validate().expect_err("meshes have no sign");
    // The library names the setting (the CLI spells it `--color sign`).
    assert_eq!(error.setting_of(), Some(glyphcast::Setting::Color));
    let error = error.to_string();
    assert!(error.starts_with("color sign: method mesh:3 "), "{error}");
}

#[test]
fn transparent_background_is_exactly_where_the_reference_sees_no_glyph() {
    let settings = RenderSettings {
        background: parse_background("none").expect("none"),
        ..Default::default()
    };
    for path in [RenderPath::Fragment, RenderPath::Compute] {
        let settings = RenderSettings { path, ..settings };
        let r = render_exactly(&signed_scene(NegativeMode::Abs), &settings);
        for (pixel, t) in r.image.rgba.chunks_exact(4).zip(&r.reference) {
            let alpha = if t.is_nan() { 0 } else { 255 };
            assert_eq!(pixel[3], alpha, "{path}: {pixel:?} at reference depth {t}");
        }
    }
}

#[test]
fn background_colours_are_written_as_their_8_bit_values() {
    let dir = common::fresh_dir("figures-background");
    let file = write_scene(&dir, "scene.json", &signed_scene(NegativeMode::Abs));
    let cases: [(&str, [u8; 4]); 6] = [
        ("white", [255, 255, 255, 255]),
        ("black", [0, 0, 0, 255]),
        ("grey", [128, 128, 128, 255]),
        ("#3366cc", [0x33, 0x66, 0xcc, 255]),
        ("10,200,30", [10, 200, 30, 255]),
        ("none", [0, 0, 0, 0]),
    ];
    for (i, (colour, expected)) in cases.iter().enumerate() {
        for path in ["fragment", "compute"] {
            let name = format!("bg{i}-{path}");
            let args = [file.as_str(), "--background", colour, "--path", path];
            let (rgba, depth) = render_cli(&args, &dir, &name);
            for (pixel, d) in rgba.chunks_exact(4).zip(&depth) {
                if d.is_nan() {
                    assert_eq!(pixel, expected, "--background {colour} --path {path}");
                } else {
                    assert_eq!(pixel[3], 255, "--background {colour}: a glyph pixel");
                }
            }
        }
    }
    for bad in ["pink", "#12345", "#12345g", "1,2", "1,2,256"] {
        let run = common::glyphcast(&["render", &file, "--background", bad]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "--background {bad}: {stderr}");
        assert!(stderr.contains("--background"), "{stderr}");
    }
}

/// Two fibre glyphs, one at 0.6 the other's size.
fn two_sizes() -> Scene {
    let fibre = fibre_tensor(4, &[(direction(0.0, 0.0), 1.0)]);
    let mut set = glyph_set(
        symmetric(4),
        vec![DVec3::new(-0.6, 0.0, 0.0), DVec3::new(0.6, 0.0, 0.0)],
        1.0,
        vec![fibre.clone(), fibre],
    );
    set.scales = vec![0.3, 0.5];
    scene(vec![set], DVec3::new(0.3, -4.0, 1.0))
}

#[test]
fn magnitude_range_ends_at_the_largest_glyph_radius_drawn() {
    let scene = two_sizes();
    let magnitude = RenderSettings {
        color: "magnitude".parse().expect("magnitude"),
        ..Default::default()
    };
    let default = render_exactly(&scene, &magnitude);
    // The largest radius drawn, from the float64 glyphs: a dense sampling of the sphere.
    let largest = default.sets[0]
        .world
        .iter()
        .map(|g| g.scale * sampled_max_radius(&g.poly, g.negative, 200_000))
        .fold(0.0, f64::max);
    let extent = SceneExtent::for_settings(&scene.camera, &default.sets, &magnitude);
    let relative = extent.max_radius / largest - 1.0;
    // The sampling is a lower bound within about 1e-5 of the maximum.
    assert!(
        (0.0..1e-4).contains(&relative),
        "range top {} against the largest radius {largest}",
        extent.max_radius
    );
    let with_range = |high: f64| {
        let range = Some((0.0, high as f32));
        let settings = RenderSettings {
            color: ColorMode::Magnitude { range },
            ..magnitude
        };
        render_exactly(&scene, &settings).image.rgba
    };
    let difference = |a: &[u8], b: &[u8]| a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max();
    // The default draws what an explicit 0:largest draws, to a rounding of the last byte.
    let explicit = with_range(largest);
    let same = difference(&default.image.rgba, &explicit);
    assert!(same <= Some(1), "default against 0:{largest}: {same:?}");
    // The box's half-diagonal (the old default) is far above: the picture is darker.
    let diagonal = with_range(largest * 3f64.sqrt());
    let changed = difference(&default.image.rgba, &diagonal);
    assert!(
        changed > Some(40),
        "0:{largest} against the diagonal: {changed:?}"
    );
}

/// `--scale-factor 2` draws the same figure with twice the pixels each way (the same
/// framing: the glyphs cover the same share of the image, about the same place), and
/// `--dpi` is recorded in the PNG; bad values of either are usage errors that write
/// nothing.
#[test]
fn a_scale_factor_keeps_the_framing_and_dpi_is_recorded() {
    let dir = common::fresh_dir("scale-factor");
    let path = |name: &str| dir.join(name).display().to_string();
    let run = |extra: &[&str], name: &str| {
        let (png, npy) = (path(&format!("{name}.png")), path(&format!("{name}.npy")));
        let mut args = vec!["demo", "--width", "96", "--height", "72", "-o", &png];
        args.extend(["--depth-out", &npy]);
        args.extend(extra);
        let out = common::glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (shape, depth) = read_npy_f32(Path::new(&npy)).expect("npy");
        (png, shape, depth)
    };
    let (_, one_shape, one) = run(&[], "one");
    let (png, two_shape, two) = run(&["--scale-factor", "2", "--dpi", "300"], "two");
    assert_eq!(one_shape, vec![72, 96]);
    assert_eq!(two_shape, vec![144, 192]);
    // Coverage share and centroid of the glyphs, in image fractions.
    let measure = |depth: &[f32], (h, w): (usize, usize)| {
        let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for (i, d) in depth.iter().enumerate() {
            if d.is_finite() {
                n += 1.0;
                sx += ((i % w) as f64 + 0.5) / w as f64;
                sy += ((i / w) as f64 + 0.5) / h as f64;
            }
        }
        (n / (w * h) as f64, sx / n, sy / n)
    };
    let (a, b) = (measure(&one, (72, 96)), measure(&two, (144, 192)));
    assert!(a.0 > 0.05, "the demo covers {:.3}", a.0);
    assert!((a.0 - b.0).abs() < 0.01, "coverage {a:?} vs {b:?}");
    assert!(
        (a.1 - b.1).abs() < 0.01 && (a.2 - b.2).abs() < 0.01,
        "{a:?} vs {b:?}"
    );
    let reader = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()))
        .read_info()
        .unwrap();
    let dims = reader.info().pixel_dims.expect("a pHYs chunk");
    assert_eq!(
        (dims.xppu, dims.yppu, dims.unit),
        (11811, 11811, png::Unit::Meter)
    );
    for (flag, value, words) in [
        ("--scale-factor", "0", "--scale-factor 0: must be above 0"),
        ("--scale-factor", "1000", "each side 1 to 16384"),
        ("--dpi", "-3", "--dpi -3: must be above 0"),
    ] {
        let bad = path("bad.png");
        let out = common::glyphcast(&[
            "demo", "--width", "96", "--height", "72", flag, value, "-o", &bad,
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}: {stderr}");
        assert!(stderr.contains(words), "{flag} {value}: {stderr}");
        assert!(!Path::new(&bad).exists());
    }
}
