//! Features of the ray caster beyond plain depth: negative lobes shown and hidden,
//! glyphs that cut each other, the isotropic offset, the orthographic camera, colour
//! modes, and glyph sets split across storage buffers. The depth scenes are also held to
//! the reference with the robust methods (interval, affine).
use crate::common;
use glam::DVec3;
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::NegativeMode;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::HeadlessRenderer;
use glyphcast::render::{ColorMode, Method, RenderPath, RenderSettings};
use glyphcast::scene::{GlyphSet, ImageSize, Scene};

fn scene(sets: Vec<GlyphSet>, eye: DVec3, projection: Projection) -> Scene {
    Scene {
        glyph_sets: sets,
        camera: Camera {
            projection,
            eye,
            target: DVec3::ZERO,
            up: DVec3::Z,
        },
        image: ImageSize {
            width: 144,
            height: 144,
        },
    }
}

const PERSPECTIVE: Projection = Projection::Perspective { fov_y_deg: 30.0 };

/// f = (u.x)^4 - 0.8 (u.y)^4 + a little of everything else: a positive and a negative pair of lobes.
fn signed_glyph(negative: NegativeMode) -> GlyphSet {
    let pos = fibre_tensor(4, &[(direction(10.0, 15.0), 1.0)]);
    let neg = fibre_tensor(4, &[(direction(100.0, -10.0), 0.8)]);
    let coeffs: Vec<f64> = pos.iter().zip(&neg).map(|(p, n)| p - n).collect();
    let mut set = glyph_set(symmetric(4), vec![DVec3::ZERO], 1.0, vec![coeffs]);
    set.negative = negative;
    set
}

fn assert_matches_reference(
    name: &str,
    scene: &Scene,
    settings: &RenderSettings,
) -> common::Rendered {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let r = common::render_and_compare(&gpu, &mut renderer, scene, settings);
    let c = r.comparison;
    eprintln!("{name}: {c}");
    assert!(c.covered > 300, "{name}: too little coverage to judge: {c}");
    if c.holes != 0 || c.false_hits != 0 || c.median_error >= 1e-3 {
        common::save_failure_images(name, &r);
        panic!("{name}: {c}");
    }
    r
}

fn signed_scene(negative: NegativeMode) -> Scene {
    let eye = DVec3::new(0.4, -0.6, 4.0);
    scene(vec![signed_glyph(negative)], eye, PERSPECTIVE)
}

#[test]
fn negative_lobes_abs_and_hide() {
    let abs = assert_matches_reference(
        "negative_abs",
        &signed_scene(NegativeMode::Abs),
        &RenderSettings::default(),
    );
    let hide = assert_matches_reference(
        "negative_hide",
        &signed_scene(NegativeMode::Hide),
        &RenderSettings::default(),
    );
    // Hiding the negative pair removes a large part of the picture.
    let (a, h) = (abs.comparison.covered, hide.comparison.covered);
    assert!(h * 10 < a * 8, "hide covers {h} px, abs {a} px");
}

fn cutting_scene() -> Scene {
    let t = fibre_tensor(
        6,
        &[(direction(0.0, 0.0), 1.0), (direction(90.0, 0.0), 0.7)],
    );
    let u = fibre_tensor(6, &[(direction(45.0, 30.0), 1.0)]);
    let set = glyph_set(
        symmetric(6),
        vec![DVec3::new(-0.3, 0.0, 0.0), DVec3::new(0.3, 0.1, 0.1)],
        1.0,
        vec![t, u],
    );
    scene(vec![set], DVec3::new(0.5, -2.0, 3.5), PERSPECTIVE)
}

#[test]
fn glyphs_that_cut_each_other() {
    let r = assert_matches_reference("cutting", &cutting_scene(), &RenderSettings::default());
    // Both glyphs are visible in the result: depths from both centres' neighbourhoods.
    assert!(r.comparison.p99_error < 1e-2, "{}", r.comparison);
}

fn offset_scene() -> Scene {
    let t = fibre_tensor(
        8,
        &[(direction(0.0, 0.0), 1.0), (direction(90.0, 0.0), 1.0)],
    );
    let set = glyph_set(symmetric(8), vec![DVec3::ZERO], 1.0, vec![t]);
    scene(vec![set], DVec3::new(0.2, -0.3, 4.0), PERSPECTIVE)
}

const OFFSET: f32 = 0.15;

#[test]
fn isotropic_offset_matches_reference() {
    // The fixed step samples the radial form, which takes the offset as it is.
    let settings = RenderSettings {
        method: Method::Fixed,
        offset: OFFSET,
        ..Default::default()
    };
    assert_matches_reference("offset", &offset_scene(), &settings);
}

fn orthographic_scene() -> Scene {
    let t = fibre_tensor(
        4,
        &[(direction(30.0, 20.0), 1.0), (direction(120.0, 0.0), 0.6)],
    );
    let u = fibre_tensor(4, &[(direction(-30.0, 40.0), 1.0)]);
    let set = glyph_set(
        symmetric(4),
        vec![DVec3::new(-0.55, 0.0, 0.0), DVec3::new(0.55, 0.0, 0.0)],
        0.5,
        vec![t, u],
    );
    let ortho = Projection::Orthographic { height: 2.4 };
    scene(vec![set], DVec3::new(1.0, -3.0, 2.0), ortho)
}

#[test]
fn orthographic_camera_matches_reference() {
    assert_matches_reference(
        "orthographic",
        &orthographic_scene(),
        &RenderSettings::default(),
    );
}

/// The robust methods on the same scenes: negative lobes shown and hidden (h = |f| and
/// max(f, 0) in the ranges), glyphs cutting each other, the offset (the w |q|^n term of
/// the ranges) and the orthographic camera (a constant pixel footprint).
#[test]
fn robust_methods_match_reference_on_feature_scenes() {
    for method in [Method::Interval, Method::Affine] {
        let plain = RenderSettings {
            method,
            ..Default::default()
        };
        let offset = RenderSettings {
            offset: OFFSET,
            ..plain
        };
        let cases = [
            ("negative_abs", signed_scene(NegativeMode::Abs), plain),
            ("negative_hide", signed_scene(NegativeMode::Hide), plain),
            ("cutting", cutting_scene(), plain),
            ("offset", offset_scene(), offset),
            ("orthographic", orthographic_scene(), plain),
        ];
        for (name, scene, settings) in cases {
            assert_matches_reference(&format!("{name}-{method:?}"), &scene, &settings);
        }
    }
}

/// Uniform colour: every covered pixel is grey; direction colour: a lobe along x is red;
/// magnitude colour varies along the lobe.
#[test]
fn colour_modes() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let t = fibre_tensor(6, &[(DVec3::X, 1.0)]);
    let s = scene(
        vec![glyph_set(symmetric(6), vec![DVec3::ZERO], 1.0, vec![t])],
        DVec3::new(0.0, -0.5, 4.0),
        PERSPECTIVE,
    );
    let sets = prepare_scene(&s, 0.0).expect("prepare");
    let mut render = |color| {
        let settings = RenderSettings {
            color,
            ..Default::default()
        };
        renderer
            .render_view(
                &gpu,
                &sets,
                &glyphcast::FrameView::new(&s.camera, 144, 144),
                &settings,
            )
            .expect("render")
    };
    let uniform = render(ColorMode::Uniform([0.5, 0.5, 0.5]));
    let direction = render(ColorMode::Direction);
    let magnitude = render(ColorMode::Magnitude { range: None });
    let covered: Vec<usize> = (0..144 * 144)
        .filter(|&i| !uniform.distance[i].is_nan())
        .collect();
    assert!(covered.len() > 500);
    for &i in &covered {
        let p = &uniform.rgba[4 * i..4 * i + 3];
        assert!(
            p[0] == p[1] && p[1] == p[2],
            "uniform grey expected, got {p:?}"
        );
    }
    // Surface points of a lobe along x mostly lie in directions near x; only its waist,
    // close to the centre, points elsewhere.
    let red = covered
        .iter()
        .filter(|&&i| {
            let d = &direction.rgba[4 * i..4 * i + 3];
            d[0] > d[1] && d[0] > d[2]
        })
        .count();
    assert!(
        red * 10 > covered.len() * 8,
        "{red} of {} pixels red-dominant",
        covered.len()
    );
    // Magnitude: the lobe's tips (far from the centre) and its waist differ in colour.
    let distinct: std::collections::HashSet<[u8; 3]> = covered
        .iter()
        .map(|&i| {
            [
                magnitude.rgba[4 * i],
                magnitude.rgba[4 * i + 1],
                magnitude.rgba[4 * i + 2],
            ]
        })
        .collect();
    assert!(distinct.len() > 50, "the colormap varies over the glyph");
}

/// A set split across several storage buffers renders exactly the same image.
#[test]
fn split_storage_buffers_leave_the_image_unchanged() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let mut centers = Vec::new();
    let mut coeffs = Vec::new();
    for k in 0..30 {
        let (x, y) = ((k % 6) as f64 - 2.5, (k / 6) as f64 - 2.0);
        centers.push(DVec3::new(x, y, 0.0));
        coeffs.push(fibre_tensor(
            4,
            &[
                (direction(12.0 * k as f64, 10.0), 1.0),
                (direction(12.0 * k as f64 + 80.0, 0.0), 0.7),
            ],
        ));
    }
    let sets = vec![glyph_set(symmetric(4), centers, 0.45, coeffs)];
    let s = scene(sets, DVec3::new(0.0, -6.0, 6.0), PERSPECTIVE);
    let prepared = prepare_scene(&s, 0.0).expect("prepare");
    let settings = RenderSettings::default();
    let whole = renderer
        .render_view(
            &gpu,
            &prepared,
            &glyphcast::FrameView::new(&s.camera, 144, 144),
            &settings,
        )
        .expect("render");
    // 7 glyphs of 15 float coefficients per buffer: 30 glyphs need 5 buffers.
    renderer
        .pass_mut()
        .set_storage_buffer_limit(Some(7 * 15 * 4));
    let split = renderer
        .render_view(
            &gpu,
            &prepared,
            &glyphcast::FrameView::new(&s.camera, 144, 144),
            &settings,
        )
        .expect("render");
    assert_eq!(whole.draws, 1);
    assert_eq!(split.draws, 5);
    assert!(whole.rgba == split.rgba, "colour differs after splitting");
    let same = whole
        .distance
        .iter()
        .zip(&split.distance)
        .all(|(a, b)| a.to_bits() == b.to_bits());
    assert!(same, "depth differs after splitting");
    // A limit below one glyph is an error, not a crash.
    renderer.pass_mut().set_storage_buffer_limit(Some(8));
    let err = renderer
        .render_view(
            &gpu,
            &prepared,
            &glyphcast::FrameView::new(&s.camera, 144, 144),
            &settings,
        )
        .expect_err("too small a limit");
    assert!(err.to_string().contains("storage buffer"), "{err}");
}

/// Glyph sets that share a layout and a negative mode share buffers and one draw, on the
/// box pass and on the compute path: thirty one-glyph sets render exactly as one set of
/// thirty, and a scene mixing layouts and modes draws once per layout and mode and still
/// matches the reference.
#[test]
fn glyph_sets_that_share_a_pipeline_share_a_draw() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let glyphs: Vec<(DVec3, Vec<f64>)> = (0..30)
        .map(|k| {
            let (x, y) = ((k % 6) as f64 - 2.5, (k / 6) as f64 - 2.0);
            let fibres = [
                (direction(12.0 * k as f64, 10.0), 1.0),
                (direction(12.0 * k as f64 + 80.0, 0.0), 0.6),
            ];
            (DVec3::new(x, y, 0.0), fibre_tensor(4, &fibres))
        })
        .collect();
    let one_set = vec![glyph_set(
        symmetric(4),
        glyphs.iter().map(|g| g.0).collect(),
        0.45,
        glyphs.iter().map(|g| g.1.clone()).collect(),
    )];
    let many_sets: Vec<GlyphSet> = glyphs
        .iter()
        .map(|(c, t)| glyph_set(symmetric(4), vec![*c], 0.45, vec![t.clone()]))
        .collect();
    let eye = DVec3::new(0.0, -6.0, 6.0);
    for path in [RenderPath::Fragment, RenderPath::Compute] {
        let settings = RenderSettings {
            path,
            ..RenderSettings::default()
        };
        let mut render = |sets: Vec<GlyphSet>| {
            let s = scene(sets, eye, PERSPECTIVE);
            let prepared = prepare_scene(&s, 0.0).expect("prepare");
            renderer
                .render_view(
                    &gpu,
                    &prepared,
                    &glyphcast::FrameView::new(&s.camera, 144, 144),
                    &settings,
                )
                .expect("render")
        };
        let whole = render(one_set.clone());
        let split = render(many_sets.clone());
        assert_eq!(
            whole.draws, split.draws,
            "{path:?}: one draw for all thirty sets"
        );
        assert!(whole.rgba == split.rgba, "{path:?}: colour differs");
        let same = whole
            .distance
            .iter()
            .zip(&split.distance)
            .all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "{path:?}: depth differs");
    }
    // Order 2 and order 4 with abs and hide, interleaved: three draws.
    let mut mixed = many_sets;
    for (k, set) in mixed.iter_mut().enumerate() {
        if k % 3 == 1 {
            set.negative = NegativeMode::Hide;
        }
    }
    for k in 0..5 {
        let tensor = fibre_tensor(2, &[(direction(30.0 * k as f64, 0.0), 1.0)]);
        let center = DVec3::new(k as f64 - 2.0, 2.5, 0.5);
        mixed.insert(
            4 * k,
            glyph_set(symmetric(2), vec![center], 0.4, vec![tensor]),
        );
    }
    let s = scene(mixed, eye, PERSPECTIVE);
    let r = assert_matches_reference("mixed-sets", &s, &RenderSettings::default());
    assert_eq!(r.image.draws, 3);
}

/// The camera inside a glyph's oriented box, outside the glyph (the accuracy suite's
/// `camera-inside-box`): the box is cut by the near plane and drawn inside out. The scene
/// must really put the eye in the box, the glyph around the eye must be seen (before the
/// fix, its box's front faces were clipped and nothing of it was drawn), and the depth
/// must match the reference.
#[test]
fn camera_inside_a_glyph_box() {
    let scene = glyphcast::accuracy::suite::camera_inside_box(160);
    let sets = prepare_scene(&scene, 0.0).expect("preparing");
    let set = &sets[0];
    let [x, y, z, w, ex, ey, ez, _] = set.boxes[0];
    let rotation = glam::DQuat::from_xyzw(x as f64, y as f64, z as f64, w as f64);
    let [cx, cy, cz, radius] = set.instances[0].map(f64::from);
    let local = rotation.inverse() * (scene.camera.eye - DVec3::new(cx, cy, cz)) / radius;
    let extent = DVec3::new(ex as f64, ey as f64, ez as f64);
    assert!(
        local.abs().cmplt(extent).all(),
        "the eye is outside the box: {local} against {extent}"
    );
    let glyph = &set.world[0];
    let offset = scene.camera.eye - glyph.center;
    let surface = glyph.scale * glyph.poly.eval(offset.normalize()).abs();
    assert!(
        offset.length() > 2.0 * surface,
        "the eye must be outside the glyph: {} against {surface}",
        offset.length()
    );

    let r = assert_matches_reference("camera-inside-box", &scene, &RenderSettings::default());
    save_image("camera-inside-box", &r);
    // Depths within the first glyph's bounding sphere around the eye: that glyph is seen.
    let near = r
        .image
        .distance
        .iter()
        .filter(|d| d.is_finite() && (**d as f64) < radius)
        .count();
    assert!(
        near > r.image.distance.len() / 10,
        "only {near} pixels show the glyph around the eye"
    );
}

/// Sizes and distances over 10^6 in one view (the accuracy suite's `scale-range-1e6`):
/// each of the three glyphs, at distances near 0.01, 10 and 10^4, is drawn (before
/// reversed depth, the near plane sat at 1e-5 of the far one and cut the nearest away)
/// and the depth matches the reference.
#[test]
fn sizes_and_distances_over_a_million() {
    let scene = glyphcast::accuracy::suite::scale_range(160);
    let r = assert_matches_reference("scale-range", &scene, &RenderSettings::default());
    save_image("scale-range", &r);
    for (near, far) in [(0.005, 0.02), (5.0, 20.0), (5e3, 2e4)] {
        let pixels = r
            .image
            .distance
            .iter()
            .filter(|d| (near..far).contains(&(**d as f64)))
            .count();
        assert!(
            pixels > 100,
            "only {pixels} pixels at distances {near} to {far}"
        );
    }
}

/// Writes the rendered image to the tests' output folder, to look at.
fn save_image(name: &str, r: &common::Rendered) {
    let path = common::output_dir().join(format!("{name}.png"));
    let written =
        glyphcast::io::png::write_png_rgba8(&path, r.image.width, r.image.height, &r.image.rgba);
    assert!(written.is_ok(), "{}: {written:?}", path.display());
}

/// The coefficients reach the fragment shader as flat inputs: a device that takes fewer
/// components than a layout needs gets an error that names the limit, not a pipeline
/// that breaks the limit. 64 is the Vulkan minimum and what order 8 needs.
#[test]
fn too_few_varying_components_is_a_clear_error() {
    use ash::vk;
    use glyphcast::glyph::{Symmetry, TensorLayout};
    use glyphcast::render::raycast::{RayCastPass, TargetFormats, varying_components};
    let gpu = common::gpu();
    let layout = |order| TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    };
    use glyphcast::render::ShapeShader;
    assert_eq!(varying_components(layout(8), ShapeShader::Polynomial), 64);
    assert_eq!(varying_components(layout(12), ShapeShader::Polynomial), 108);
    // A plane glyph passes its T's 15 coefficients after D's 28: within the minimum; a
    // ratio glyph its T's and Q's.
    assert_eq!(varying_components(layout(6), ShapeShader::Polynomial), 44);
    assert_eq!(varying_components(layout(6), ShapeShader::Plane), 60);
    assert_eq!(varying_components(layout(6), ShapeShader::Ratio), 76);
    assert!(
        gpu.context().max_varying_components()
            >= varying_components(layout(12), ShapeShader::Polynomial)
    );
    let context = gpu.context().clone().with_max_varying_components(64);
    assert_eq!(context.max_varying_components(), 64);
    let formats = TargetFormats {
        color: vk::Format::R8G8B8A8_UNORM,
        depth: vk::Format::D32_SFLOAT,
        distance: None,
    };
    let mut pass = RayCastPass::new(&context, formats).expect("pass");
    pass.pipeline(layout(8), Method::Exact)
        .expect("order 8 fits");
    let err = pass
        .pipeline(layout(10), Method::Exact)
        .expect_err("order 10 needs 84 components");
    let text = err.to_string();
    assert!(
        text.contains("order 10") && text.contains("maxVertexOutputComponents"),
        "{text}"
    );
    drop(pass);
    assert!(
        gpu.validation_errors().is_empty(),
        "{:?}",
        gpu.validation_errors()
    );
}
