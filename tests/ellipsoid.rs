//! DTI ellipsoids (`--glyph ellipsoid`, issue 13): the GPU's closed-form quadric against
//! the float64 reference and against an independent analytic solution from D^-1; the
//! volume path from `glyphcast fit`'s DTI; colouring by the principal eigenvector; the
//! errors for what has no ellipsoid.
use crate::common;
use common::{expect_failure, fresh_dir, glyphcast};
use glam::{DMat3, DQuat, DVec3, EulerRot};
use glyphcast::camera::Camera;
use glyphcast::demo::{glyph_set, symmetric};
use glyphcast::glyph::GlyphShape;
use glyphcast::glyph::reference::reference_depth;
use glyphcast::io::npy::read_npy_f32;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::{Method, RenderSettings};
use glyphcast::scene::{GlyphSet, Scene};
use std::path::Path;

/// The unique entries (xx, xy, xz, yy, yz, zz) of R diag(eigenvalues) R^T.
fn tensor(eigenvalues: [f64; 3], rotation: DQuat) -> Vec<f64> {
    let r = DMat3::from_quat(rotation);
    let d = r * DMat3::from_diagonal(DVec3::from_array(eigenvalues)) * r.transpose();
    vec![
        d.x_axis.x, d.y_axis.x, d.z_axis.x, d.y_axis.y, d.z_axis.y, d.z_axis.z,
    ]
}

/// Five tensors in a row: prolate, oblate, nearly isotropic, strongly linear (1:100 in
/// eigenvalues, 1:10 in semi-axes) and a tilted general one, in DTI units (mm^2/s).
fn ellipsoid_set() -> GlyphSet {
    let rotation = |a: f64, b: f64, c: f64| DQuat::from_euler(EulerRot::ZYX, a, b, c);
    let tensors = vec![
        tensor([1.7e-3, 0.3e-3, 0.3e-3], rotation(0.4, 0.3, 0.0)),
        tensor([1.2e-3, 1.1e-3, 0.2e-3], rotation(-0.5, 0.8, 0.2)),
        tensor([0.8e-3, 0.75e-3, 0.7e-3], rotation(1.0, 0.1, 0.3)),
        tensor([2.0e-3, 0.02e-3, 0.02e-3], rotation(0.9, -0.6, 0.4)),
        tensor([1.4e-3, 0.7e-3, 0.25e-3], rotation(2.0, 1.1, -0.7)),
    ];
    let centers = (0..5)
        .map(|i| DVec3::new(i as f64 - 2.0, 0.0, 0.0))
        .collect();
    // Semi-axes of ~0.04: a scale of 10 makes the longest about 0.45 world units.
    let mut set = glyph_set(symmetric(2), centers, 10.0, tensors);
    set.shape = GlyphShape::Ellipsoid;
    set
}

fn scene_of(set: GlyphSet, eye: DVec3) -> Scene {
    let mut scene = glyphcast::accuracy::suite::scene(vec![set], eye, 160);
    scene.image.width = 320;
    scene
}

/// The analytic depth: per pixel the smallest t > 0 with (p - c)^T (s^2 D)^-1 (p - c) = 1
/// over the glyphs, with D inverted directly (no eigen decomposition: independent of
/// the renderer's float64 path).
fn analytic_depth(set: &GlyphSet, camera: &Camera, w: u32, h: u32) -> Vec<f64> {
    let inverses: Vec<DMat3> = set
        .coeffs
        .iter()
        .zip(&set.scales)
        .map(|(t, s)| {
            let d = DMat3::from_cols_array(&[t[0], t[1], t[2], t[1], t[3], t[4], t[2], t[4], t[5]]);
            (d * (s * s)).inverse()
        })
        .collect();
    let mut depth = vec![f64::NAN; (w * h) as usize];
    for j in 0..h {
        for i in 0..w {
            let ray = camera.ray(i, j, w, h);
            let mut nearest = f64::INFINITY;
            for (center, q) in set.centers.iter().zip(&inverses) {
                let a = ray.origin - *center;
                let (qa, qd) = (*q * a, *q * ray.dir);
                let (c2, b, c) = (ray.dir.dot(qd), 2.0 * a.dot(qd), a.dot(qa) - 1.0);
                let disc = b * b - 4.0 * c2 * c;
                if disc > 0.0 {
                    let root = (-b - disc.sqrt()) / (2.0 * c2);
                    if root > 0.0 {
                        nearest = nearest.min(root);
                    }
                }
            }
            if nearest.is_finite() {
                depth[(j * w + i) as usize] = nearest;
            }
        }
    }
    depth
}

#[test]
fn ellipsoid_depth_matches_the_analytic_quadric() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for (view, eye) in [
        ("oblique", DVec3::new(1.0, -6.0, 2.5)),
        ("above", DVec3::new(0.0, 0.01, 7.0)),
    ] {
        let scene = scene_of(ellipsoid_set(), eye);
        // --method does not matter to ellipsoids: every ray-casting one draws them the same.
        for method in [Method::Exact, Method::Fixed] {
            let settings = RenderSettings {
                method,
                ..Default::default()
            };
            let r = common::render_and_compare(&gpu, &mut renderer, &scene, &settings);
            let c = r.comparison;
            eprintln!("{view} {method}: {c}");
            // The float64 reference is the closed-form quadric too. Errors are relative to
            // the largest glyph's radius: float32 arithmetic in the normalised frame gives
            // ~1e-7 (median); near the silhouette (a small discriminant) the root loses
            // digits, so the worst pixel is allowed 1e-4.
            if c.holes != 0
                || c.false_hits != 0
                || c.median_error > 1e-6
                || c.p99_error > 1e-5
                || c.max_error > 1e-4
                || c.covered < 1200
            {
                common::save_failure_images(&format!("ellipsoid-{view}"), &r);
                panic!("{view} {method}: {c}");
            }
            let (w, h) = (scene.image.width, scene.image.height);
            let analytic = analytic_depth(&scene.glyph_sets[0], &scene.camera, w, h);
            let mut checked = 0;
            for ((&gpu_t, &reference), &exact) in
                r.image.distance.iter().zip(&r.reference).zip(&analytic)
            {
                assert_eq!(reference.is_nan(), exact.is_nan(), "reference coverage");
                if !reference.is_nan() {
                    // The reference against the independent solution: float64 rounding.
                    assert!(
                        (reference - exact).abs() < 1e-9 * exact,
                        "{reference} {exact}"
                    );
                    if !gpu_t.is_nan() {
                        let error = (gpu_t as f64 - exact).abs() / r.scale;
                        assert!(error < 1e-4, "{view}: GPU {gpu_t} vs analytic {exact}");
                        checked += 1;
                    }
                }
            }
            assert!(checked > 1200, "{checked} pixels compared");
        }
    }
}

/// The box proxy is the ellipsoid's exact extent: its half extents are the semi-axes
/// (in units of the longest), and the bounding radius is the longest semi-axis.
#[test]
fn ellipsoid_proxies_are_the_exact_extents() {
    let set = ellipsoid_set();
    let scene = scene_of(set.clone(), DVec3::new(0.0, -6.0, 0.0));
    let data = prepare_scene(&scene, 0.0).expect("prepared");
    let [prepared] = data.as_slice() else {
        panic!("one set")
    };
    for ((coeffs, instance), boxed) in set
        .coeffs
        .iter()
        .zip(&prepared.instances)
        .zip(&prepared.boxes)
    {
        let d = DMat3::from_cols_array(&[
            coeffs[0], coeffs[1], coeffs[2], coeffs[1], coeffs[3], coeffs[4], coeffs[2], coeffs[4],
            coeffs[5],
        ]);
        // Eigenvalues from the characteristic polynomial's invariants would do; the
        // largest semi-axis is sqrt of the spectral norm, found by power iteration.
        let mut v = DVec3::new(0.3, 0.5, 0.7);
        for _ in 0..500 {
            v = (d * v).normalize();
        }
        let longest = v.dot(d * v).sqrt() * 10.0;
        assert!((instance[3] as f64 - longest).abs() < 1e-6 * longest);
        let mut extents = [boxed[4], boxed[5], boxed[6]];
        extents.sort_by(f32::total_cmp);
        // The longest extent is the whole radius, padded by 1/4096.
        assert!((extents[2] - 1.0).abs() < 3e-4, "{extents:?}");
    }
    // The linear tensor: 1:100 eigenvalues give a box 1/10 as thick as it is long.
    let thin = &prepared.boxes[3];
    let mut e = [thin[4], thin[5], thin[6]];
    e.sort_by(f32::total_cmp);
    assert!(
        (e[0] - 0.1).abs() < 1e-3 && (e[1] - 0.1).abs() < 1e-3,
        "{e:?}"
    );
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A DTI volume drawn with `--glyph ellipsoid` through the CLI: its depth map matches the
/// float64 reference of the scene it saved, which carries `"shape": "ellipsoid"`.
#[test]
fn dti_volume_renders_as_ellipsoids_through_the_cli() {
    let dir = fresh_dir("ellipsoid-cli");
    let dti = common::fit_dti_small_64d(&dir);
    let (png, npy, json) = (dir.join("e.png"), dir.join("e.npy"), dir.join("e.json"));
    let out = glyphcast(&[
        "render",
        "--tensor",
        path_str(&dti),
        "--order",
        "2",
        "--glyph",
        "ellipsoid",
        "--width",
        "200",
        "--height",
        "200",
        "-o",
        path_str(&png),
        "--depth-out",
        path_str(&npy),
        "--save-scene",
        path_str(&json),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let scene = Scene::load(&json).expect("saved scene");
    let text = std::fs::read_to_string(&json).expect("scene text");
    assert!(text.contains("\"shape\": \"ellipsoid\""));
    assert!(
        scene
            .glyph_sets
            .iter()
            .all(|s| s.shape == GlyphShape::Ellipsoid)
    );
    let sets = prepare_scene(&scene, 0.0).expect("prepared");
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    assert!(world.len() > 20, "{} glyphs", world.len());
    let (w, h) = (scene.image.width, scene.image.height);
    let reference = reference_depth(&world, &scene.camera, w, h);
    let (shape, depth) = read_npy_f32(&npy).expect("depth map");
    assert_eq!(shape, [h as usize, w as usize]);
    let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
    let c = glyphcast::accuracy::compare_depth(&depth, &reference, w as usize, h as usize, scale);
    eprintln!("dti ellipsoids: {c}");
    assert_eq!((c.holes, c.false_hits), (0, 0), "{c}");
    assert!(c.max_error < 1e-4 && c.covered > 1000, "{c}");
    // The same scene drawn as the polynomial glyph ("peanut") differs: the flag matters.
    let peanut = dir.join("p.npy");
    let out = glyphcast(&[
        "render",
        "--tensor",
        path_str(&dti),
        "--order",
        "2",
        "--width",
        "200",
        "--height",
        "200",
        "-o",
        path_str(&dir.join("p.png")),
        "--depth-out",
        path_str(&peanut),
    ]);
    assert!(out.status.success());
    let (_, other) = read_npy_f32(&peanut).expect("depth map");
    let differing = depth
        .iter()
        .zip(&other)
        .filter(|(a, b)| a.is_nan() != b.is_nan() || (*a - *b).abs() > 1e-3)
        .count();
    assert!(differing > 1000, "{differing} pixels differ");
}

#[test]
fn what_has_no_ellipsoid_is_refused() {
    let dir = fresh_dir("ellipsoid-errors");
    let out_dir = dir.join("out");
    std::fs::create_dir_all(&out_dir).expect("output folder");
    let sh = common::dipy_data("func_coef.nii.gz");
    let png = out_dir.join("x.png");
    let base = ["render", "-o", path_str(&png)];
    let run = |extra: &[&str], words: &[&str]| {
        let mut args: Vec<&str> = base.to_vec();
        args.extend_from_slice(extra);
        let out = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        for word in words {
            assert!(stderr.contains(word), "{args:?}: no '{word}' in {stderr}");
        }
        assert!(!png.exists());
    };
    run(
        &[
            "--sh",
            path_str(&sh),
            "--basis",
            "dipy",
            "--glyph",
            "ellipsoid",
        ],
        &["--glyph ellipsoid", "order-2"],
    );
    run(
        &[
            "--sh",
            path_str(&sh),
            "--basis",
            "dipy",
            "--glyph",
            "peanut",
        ],
        &["--glyph", "peanut", "polynomial, ellipsoid"],
    );
    // A scene of order-4 glyphs.
    let scene = glyphcast::accuracy::suite::touching_centre(32);
    let file = dir.join("order4.json");
    std::fs::write(&file, scene.to_json()).expect("scene");
    run(
        &[path_str(&file), "--glyph", "ellipsoid"],
        &["glyph set 0", "order 2"],
    );
    // Ellipsoids are not tessellated, and have no compute ray caster.
    let mut dti_scene = scene_of(ellipsoid_set(), DVec3::new(0.0, -6.0, 0.0));
    dti_scene.image.width = 32;
    dti_scene.image.height = 32;
    let dti = dir.join("dti.json");
    std::fs::write(&dti, dti_scene.to_json()).expect("scene");
    let failure = expect_failure(
        &[
            "render",
            path_str(&dti),
            "--method",
            "mesh:2",
            "-o",
            path_str(&png),
        ],
        &out_dir,
        &["ellipsoid", "tessellated"],
    );
    eprintln!("{failure}");
    // `--path compute` is the request to change (a usage error, exit 2, as for another
    // method), refused with the path that draws them.
    let compute = glyphcast(&[
        "render",
        path_str(&dti),
        "--path",
        "compute",
        "-o",
        path_str(&png),
    ]);
    let stderr = String::from_utf8_lossy(&compute.stderr);
    assert_eq!(compute.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--path compute") && stderr.contains("ellipsoid glyphs"),
        "{stderr}"
    );
    assert!(stderr.contains("--path fragment"), "{stderr}");
    assert!(!png.exists(), "no output on a refusal");
    expect_failure(
        &[
            "render",
            path_str(&dti),
            "--offset",
            "0.1",
            "-o",
            path_str(&png),
        ],
        &out_dir,
        &["ellipsoid", "--offset"],
    );
}

/// `--color direction` colours each ellipsoid by its principal eigenvector |e1| (the DTI
/// convention): lit by ambient light alone, every pixel of an ellipsoid is the colour
/// |e1|^2.2 (linear) encoded to sRGB, whatever the surface direction there.
#[test]
fn direction_colour_is_the_principal_eigenvector() {
    use glyphcast::glyph::ellipsoid::Ellipsoid;
    use glyphcast::render::compose::colorbar::srgb_byte;
    use glyphcast::render::settings::Lighting;
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let set = ellipsoid_set();
    let scene = scene_of(set.clone(), DVec3::new(0.0, 0.01, 7.0));
    let settings = RenderSettings {
        lighting: Lighting {
            ambient: 1.0,
            specular: 0.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let r = common::render_and_compare(&gpu, &mut renderer, &scene, &settings);
    let (w, h) = (scene.image.width, scene.image.height);
    // Which glyph each pixel hits: the nearest analytic hit of that glyph alone.
    for (k, (center, coeffs)) in set.centers.iter().zip(&set.coeffs).enumerate() {
        let e1 = Ellipsoid::from_tensor(coeffs)
            .expect("ellipsoid")
            .principal_axis();
        let expected = e1.abs().to_array().map(|c| srgb_byte((c.powf(2.2)) as f32));
        let mut alone = set.clone();
        alone.centers = vec![*center];
        alone.coeffs = vec![coeffs.clone()];
        alone.scales = vec![set.scales[k]];
        let own = analytic_depth(&alone, &scene.camera, w, h);
        let mut pixels = 0;
        for (i, (&t, &all)) in own.iter().zip(&r.reference).enumerate() {
            // Pixels this glyph is the front of, away from its silhouette.
            if t.is_nan() || (t - all).abs() > 1e-9 || r.image.distance[i].is_nan() {
                continue;
            }
            let rgb = &r.image.rgba[4 * i..4 * i + 3];
            let steps = rgb.iter().zip(&expected).map(|(a, b)| a.abs_diff(*b)).max();
            assert!(steps <= Some(1), "glyph {k}: {rgb:?} vs |e1| {expected:?}");
            pixels += 1;
        }
        assert!(pixels > 20, "glyph {k}: {pixels} pixels");
    }
}
