//! Shadows (`--shadows`): each pixel's lit or shadowed state against the float64 reference
//! (`glyph::shadow`: the exact hit, its normal, the shadow ray intersected exactly with
//! every glyph), away from shadow edges; soft shadows' lit share likewise; the depth map
//! unchanged and no pixel brightened; the option through the command line, its refusals.
use crate::common;
use common::{fresh_dir, glyphcast, srgb_byte};
use glam::DVec3;
use glyphcast::camera::Camera;
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::intersect::{WorldGlyph, first_hit};
use glyphcast::glyph::shadow;
use glyphcast::io::png::read_png_rgba8;
use glyphcast::render::glyph_data::{GlyphSetData, prepare_scene};
use glyphcast::render::headless::{HeadlessRenderer, RenderedImage};
use glyphcast::render::settings::{Lighting, srgb_to_linear};
use glyphcast::render::underlay::{Underlay, UnderlayPlane, UnderlayVolume};
use glyphcast::render::{AmbientOcclusion, ColorMode, Method, RenderSettings, Shadows};
use glyphcast::scene::Scene;

/// The glyphs' uniform colour (linear RGB).
const BASE: [f32; 3] = [0.8, 0.8, 0.8];
/// Pixels whose float64 n . l is below this are left out of the comparisons: there the
/// light's terms are too small to tell a shadow in 8 bits.
const MIN_DIFFUSE: f64 = 0.1;

/// A world direction towards the light as `--light` takes it: in view coordinates of
/// `camera` (x right, y up, z towards the viewer).
fn view_light(camera: &Camera, world: DVec3) -> [f32; 3] {
    let f = camera.frame();
    let l = world.normalize();
    [l.dot(f.right), l.dot(f.up), -l.dot(f.fwd)].map(|v| v as f32)
}

/// A small sphere above a flat glyph (the order-2 form diag(1, 1, 0.02)), lit from the
/// side: the sphere's shadow falls on the flat glyph.
fn sphere_above_flat(size: u32) -> (Scene, DVec3) {
    let layout = symmetric(2);
    // Order-2 coefficients xx, xy, xz, yy, yz, zz.
    let flat = glyph_set(
        layout,
        vec![DVec3::ZERO],
        1.0,
        vec![vec![1.0, 0.0, 0.0, 1.0, 0.0, 0.02]],
    );
    let ball = glyph_set(
        layout,
        vec![DVec3::new(0.0, 0.0, 0.6)],
        0.25,
        vec![vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0]],
    );
    let scene =
        glyphcast::accuracy::suite::scene(vec![flat, ball], DVec3::new(0.6, -2.2, 3.2), 128);
    let mut scene = scene;
    scene.image.width = size;
    scene.image.height = size;
    (scene, DVec3::new(1.0, 0.25, 0.8))
}

/// Nine order-4 glyphs of two fibre populations each, close enough that lobes shadow
/// their own glyph and the neighbours, lit from the side.
fn fibre_field(size: u32) -> (Scene, DVec3) {
    let mut centers = Vec::new();
    let mut coeffs = Vec::new();
    for j in 0..3 {
        for i in 0..3 {
            let k = (3 * j + i) as f64;
            centers.push(DVec3::new(i as f64 - 1.0, j as f64 - 1.0, 0.0) * 0.9);
            coeffs.push(fibre_tensor(
                4,
                &[
                    (direction(20.0 * k, 15.0 + 5.0 * k), 1.0),
                    (direction(20.0 * k + 75.0, 50.0 - 4.0 * k), 0.8),
                ],
            ));
        }
    }
    let set = glyph_set(symmetric(4), centers, 0.55, coeffs);
    let scene = glyphcast::accuracy::suite::scene(vec![set], DVec3::new(0.8, -2.6, 4.0), size);
    (scene, DVec3::new(-1.0, 0.4, 0.6))
}

fn settings(camera: &Camera, light: DVec3, shadows: Shadows) -> RenderSettings {
    RenderSettings {
        method: Method::Exact,
        color: ColorMode::Uniform(BASE),
        lighting: Lighting {
            direction: view_light(camera, light),
            ..Lighting::default()
        },
        shadows,
        ..Default::default()
    }
}

/// The scene's glyphs, and the scene drawn without shadows and with `shadows`; the two
/// depth maps are held to be the same, bit for bit.
fn render_pair(
    gpu: &glyphcast::vk::Gpu,
    renderer: &mut HeadlessRenderer,
    scene: &Scene,
    light: DVec3,
    shadows: Shadows,
) -> (Vec<GlyphSetData>, RenderedImage, RenderedImage) {
    render_changed(gpu, renderer, (scene, None), light, 0.0, |s| {
        s.shadows = shadows
    })
}

/// The scene's glyphs, and the scene drawn with the test's settings (`ambient` their
/// ambient term, and no highlight, when above 0) and with those settings changed by
/// `change`; the two depth maps are
/// held to be the same, bit for bit.
fn render_changed(
    gpu: &glyphcast::vk::Gpu,
    renderer: &mut HeadlessRenderer,
    (scene, underlay): (&Scene, Option<&Underlay>),
    light: DVec3,
    ambient: f32,
    change: impl Fn(&mut RenderSettings),
) -> (Vec<GlyphSetData>, RenderedImage, RenderedImage) {
    let sets = prepare_scene(scene, 0.0).expect("preparing");
    let (w, h) = (scene.image.width, scene.image.height);
    let view = glyphcast::FrameView::new(&scene.camera, w, h).with_underlay(underlay);
    let mut base = settings(&scene.camera, light, Shadows::Off);
    if ambient > 0.0 {
        // A strong ambient term and no highlight, so that no channel saturates.
        base.lighting.ambient = ambient;
        base.lighting.specular = 0.0;
    }
    let mut changed = base;
    change(&mut changed);
    let mut draw = |settings: &RenderSettings| {
        renderer
            .render_view(gpu, &sets, &view, settings)
            .expect("rendering")
    };
    let (off, on) = (draw(&base), draw(&changed));
    assert_eq!(off.distance.len(), on.distance.len());
    assert!(
        crate::common::differing_distances(&off, &on) == 0,
        "{changed:?}: the depth map changed"
    );
    (sets, off, on)
}

/// Per pixel, from the float64 reference: the hit's n . l and the lit share of the light
/// (rays towards a disc of `rays` samples in the pixel's pattern when above 1), or None
/// for a miss.
fn reference_visibility(
    scene: &Scene,
    glyphs: &[WorldGlyph],
    light: DVec3,
    rays: u32,
    tan_radius: f64,
) -> Vec<Option<(f64, f64)>> {
    let light = light.normalize();
    let (w, h) = (scene.image.width, scene.image.height);
    let hits = hits(scene, glyphs);
    (0..(w * h) as usize)
        .map(|k| {
            let (g, hit, dir) = hits[k]?;
            let glyph = &glyphs[g];
            let normal = shadow::surface_normal(glyph, hit);
            let n = if normal.dot(-dir) < 0.0 {
                -normal
            } else {
                normal
            };
            let pattern = pattern_of(k, w as usize);
            let v = shadow::visibility(glyph, hit, dir, (light, rays, tan_radius), pattern, glyphs);
            Some((n.dot(light), v))
        })
        .collect()
}

/// Per pixel of `scene`, row by row: the float64 nearest hit among `glyphs` (the glyph's
/// index, the hit, the ray's unit direction), or None for a miss.
fn hits(scene: &Scene, glyphs: &[WorldGlyph]) -> Vec<Option<(usize, DVec3, DVec3)>> {
    let (w, h) = (scene.image.width, scene.image.height);
    let mut out = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let ray = scene.camera.ray(i, j, w, h);
            let nearest = glyphs
                .iter()
                .enumerate()
                .filter_map(|(g, glyph)| first_hit(&ray, glyph).map(|t| (t, g)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            out.push(nearest.map(|(t, g)| (g, ray.origin + t * ray.dir, ray.dir)));
        }
    }
    out
}

/// The pattern of rays of pixel `k` of a `w`-wide image.
fn pattern_of(k: usize, w: usize) -> shadow::SamplePattern {
    shadow::SamplePattern::for_pixel((k % w) as u32, (k / w) as u32)
}

/// The float64 shares that pixel (i, j) of a `w`-wide image is held to, each cast with
/// the pixel's own pattern of rays (`share(n)`: the share at the hit, or plane point, of
/// pixel n): its own share where the pixel `fits` it; else the range of the shares at its
/// own and its eight neighbours' points, where they differ by at most `spread` (the
/// hit's float32 rounding may move a ray across an edge that close). None: left out (no
/// share, or near a silhouette or a steeper edge).
fn share_range(
    share: impl Fn(usize) -> Option<f64>,
    (w, i, j): (usize, usize, usize),
    spread: f64,
    fits: impl Fn((f64, f64)) -> bool,
) -> Option<(f64, f64)> {
    let own = share(j * w + i)?;
    if fits((own, own)) {
        return Some((own, own));
    }
    let (lo, hi) = neighbour_range(share, w, i, j)?;
    (hi - lo <= spread + 1e-9).then_some((lo, hi))
}

/// Pixels away from shadow edges and silhouettes: the pixel and its eight neighbours hit
/// a glyph and have the same lit share, and the pixel's n . l is at least MIN_DIFFUSE;
/// the pixel's lit share for each.
fn interior(reference: &[Option<(f64, f64)>], w: usize, h: usize) -> Vec<Option<f64>> {
    let mut out = vec![None; w * h];
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let Some((diffuse, v)) = reference[j * w + i] else {
                continue;
            };
            let same = (j - 1..=j + 1).all(|y| {
                (i - 1..=i + 1).all(|x| reference[y * w + x].is_some_and(|(_, u)| u == v))
            });
            if same && diffuse >= MIN_DIFFUSE {
                out[j * w + i] = Some(v);
            }
        }
    }
    out
}

/// The lowest and highest of `value` over pixel (i, j) of a `w`-wide image and its eight
/// neighbours; None where one of them has none.
fn neighbour_range(
    value: impl Fn(usize) -> Option<f64>,
    w: usize,
    i: usize,
    j: usize,
) -> Option<(f64, f64)> {
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for y in j - 1..=j + 1 {
        for x in i - 1..=i + 1 {
            let v = value(y * w + x)?;
            range = (range.0.min(v), range.1.max(v));
        }
    }
    Some(range)
}

/// The channels of pixel `k` of `on` that are not the pixel of `off` with a share 1 - v of
/// a lighting term taken away, for any v in `shares` (`term`: the term's linear value of
/// channel c, given that channel's linear value in `off`), as (channel, byte, lowest and
/// highest byte expected). Both images are rounded to 8 bits: up to half a step each,
/// and the encoding's slope, so a byte within 1.5 of the range passes.
fn share_mismatches(
    off: &RenderedImage,
    on: &RenderedImage,
    k: usize,
    (lo, hi): (f64, f64),
    term: impl Fn(usize, f64) -> f64,
) -> Vec<(usize, f64, f64, f64)> {
    (0..3)
        .filter_map(|c| {
            let full = f64::from(srgb_to_linear(off.rgba[4 * k + c]));
            let byte = |v: f64| srgb_byte(full - (1.0 - v) * term(c, full));
            let got = f64::from(on.rgba[4 * k + c]);
            (got < byte(lo) - 1.5 || got > byte(hi) + 1.5).then_some((c, got, byte(lo), byte(hi)))
        })
        .collect()
}

fn glyphs_of(sets: &[GlyphSetData]) -> Vec<WorldGlyph> {
    sets.iter().flat_map(|s| s.world.iter().cloned()).collect()
}

fn save(name: &str, image: &RenderedImage) {
    let path = common::output_dir().join(format!("{name}.png"));
    let _ = glyphcast::io::png::write_png_rgba8(&path, image.width, image.height, &image.rgba);
}

/// Hard shadows: every pixel away from shadow edges is shadowed (changed from the render
/// without shadows) exactly where the float64 shadow ray is blocked, and otherwise keeps
/// its colour bit for bit; the depth map is the one without shadows.
#[test]
fn hard_shadows_match_the_float64_reference() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    for (name, (scene, light)) in [
        ("sphere-above-flat", sphere_above_flat(128)),
        ("fibre-field", fibre_field(128)),
    ] {
        let (sets, off, on) = render_pair(&gpu, &mut renderer, &scene, light, Shadows::Hard);
        save(&format!("shadows-{name}-off"), &off);
        save(&format!("shadows-{name}-hard"), &on);
        let (w, h) = (scene.image.width as usize, scene.image.height as usize);
        let glyphs = glyphs_of(&sets);
        let reference = reference_visibility(&scene, &glyphs, light, 1, 0.0);
        let eligible = interior(&reference, w, h);
        let (mut shadowed, mut lit, mut wrong) = (0, 0, Vec::new());
        for (k, v) in eligible.iter().enumerate() {
            let Some(v) = *v else { continue };
            if off.distance[k].is_nan() {
                wrong.push((k % w, k / w, "no GPU hit"));
                continue;
            }
            let changed = off.rgba[4 * k..4 * k + 4] != on.rgba[4 * k..4 * k + 4];
            match (v == 0.0, changed) {
                (true, true) => shadowed += 1,
                (false, false) => lit += 1,
                (true, false) => wrong.push((k % w, k / w, "lit, reference shadowed")),
                (false, true) => wrong.push((k % w, k / w, "shadowed, reference lit")),
            }
        }
        eprintln!(
            "{name}: {shadowed} shadowed and {lit} lit pixels agree, {} wrong",
            wrong.len()
        );
        assert!(
            wrong.is_empty(),
            "{name}: {:?}",
            &wrong[..wrong.len().min(20)]
        );
        assert!(
            shadowed >= 100 && lit >= 500,
            "{name}: {shadowed} shadowed, {lit} lit"
        );
        // Shadowing only takes light away.
        let brighter = (0..w * h * 4).filter(|&c| on.rgba[c] > off.rgba[c]).count();
        assert_eq!(brighter, 0, "{name}: channels brightened");
    }
}

/// The frame's hits are read in bands of rows when they are larger than a storage buffer
/// may be (the device's range, here a cap of a few rows): the picture is the same, bit
/// for bit, as with one band.
#[test]
fn hits_read_in_bands_give_the_same_shadows() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (scene, light) = fibre_field(120);
    let sets = prepare_scene(&scene, 0.0).expect("preparing");
    let (w, h) = (scene.image.width, scene.image.height);
    let view = glyphcast::FrameView::new(&scene.camera, w, h);
    let mut hard = settings(&scene.camera, light, Shadows::Hard);
    hard.ambient_occlusion = AmbientOcclusion::On { reach: 1.0 };
    let whole = renderer
        .render_view(&gpu, &sets, &view, &hard)
        .expect("rendering");
    // 7 rows of 4-byte distances after the 16-byte header: 18 bands of 120 rows (the
    // nine glyphs' coefficients, 15 floats each, fit in one buffer still).
    let cap = 16 + 7 * 4 * u64::from(w);
    renderer.pass_mut().set_storage_buffer_limit(Some(cap));
    let banded = renderer
        .render_view(&gpu, &sets, &view, &hard)
        .expect("rendering in bands");
    renderer.pass_mut().set_storage_buffer_limit(None);
    let off = renderer
        .render_view(
            &gpu,
            &sets,
            &view,
            &settings(&scene.camera, light, Shadows::Off),
        )
        .expect("rendering");
    let darkened = (0..(w * h) as usize)
        .filter(|&k| whole.rgba[4 * k..4 * k + 4] != off.rgba[4 * k..4 * k + 4])
        .count();
    assert!(darkened >= 200, "{darkened} pixels darkened");
    let differ = (0..(w * h) as usize)
        .filter(|&k| whole.rgba[4 * k..4 * k + 4] != banded.rgba[4 * k..4 * k + 4])
        .count();
    assert_eq!(differ, 0, "pixels that differ between one band and 18");
    gpu.check_validation().expect("validation");
}

/// Soft shadows: each pixel's colour is the unshadowed one with its light terms scaled by
/// a lit share that the float64 reference, casting the pixel's own pattern of rays, gives
/// the pixel's hit or one of its eight neighbours' hits (within the 8-bit rounding of
/// both images), where those shares differ by at most two of the 16 rays (away from
/// silhouettes), penumbra included.
#[test]
fn soft_shadows_match_the_float64_lit_share() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (scene, light) = sphere_above_flat(128);
    let radius_deg = 8.0f32;
    let soft = Shadows::Soft { radius_deg };
    let (sets, off, on) = render_pair(&gpu, &mut renderer, &scene, light, soft);
    save("shadows-soft", &on);
    let (w, h) = (scene.image.width as usize, scene.image.height as usize);
    let glyphs = glyphs_of(&sets);
    let tan = f64::from(radius_deg).to_radians().tan();
    let reference = reference_visibility(&scene, &glyphs, light, 16, tan);
    let hits = hits(&scene, &glyphs);
    let ambient = f64::from(Lighting::default().ambient);
    // The light's terms: what is left above the ambient term.
    let term = |c: usize, full: f64| full - f64::from(BASE[c]) * ambient;
    let (mut compared, mut partial, mut wrong) = (0, 0, Vec::new());
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let k = j * w + i;
            let Some((diffuse, v)) = reference[k] else {
                continue;
            };
            if diffuse < MIN_DIFFUSE {
                continue;
            }
            // The pixel's rays cast from its neighbours' hits.
            let share = |n: usize| {
                let (g, hit, dir) = hits[n]?;
                let light = (light.normalize(), 16, tan);
                let pattern = pattern_of(k, w);
                Some(shadow::visibility(
                    &glyphs[g], hit, dir, light, pattern, &glyphs,
                ))
            };
            let fits = |r| share_mismatches(&off, &on, k, r, term).is_empty();
            let Some(range) = share_range(share, (w, i, j), 2.0 / 16.0, fits) else {
                continue;
            };
            compared += 1;
            partial += usize::from(v > 0.0 && v < 1.0);
            for (c, got, low, high) in share_mismatches(&off, &on, k, range, term) {
                wrong.push((i, j, c, got, low, high));
            }
        }
    }
    eprintln!(
        "soft: {compared} pixels, {partial} in the penumbra, {} wrong",
        wrong.len()
    );
    assert!(wrong.is_empty(), "{:?}", &wrong[..wrong.len().min(20)]);
    assert!(
        compared > 1000 && partial >= 30,
        "{compared} compared, {partial} partial"
    );
}

/// Ambient occlusion: each pixel's colour is the unoccluded one less the ambient term's
/// occluded share, for a share that the float64 reference (`glyph::shadow::ambient_share`:
/// the pixel's own 16 occlusion rays intersected exactly with every glyph, within the
/// reach) gives the pixel's hit or one of its eight neighbours' hits (within the 8-bit
/// rounding of both images), where those shares differ by at most two of the 16 rays
/// (away from silhouettes); the depth map does not change, no channel brightens.
#[test]
fn ambient_occlusion_matches_the_float64_share() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let ambient = 0.6;
    for (name, (scene, light), reach) in [
        ("sphere-above-flat", sphere_above_flat(128), 1.0f32),
        ("fibre-field", fibre_field(128), 0.5),
    ] {
        let occlusion = AmbientOcclusion::On { reach };
        let (sets, off, on) =
            render_changed(&gpu, &mut renderer, (&scene, None), light, ambient, |s| {
                s.ambient_occlusion = occlusion;
            });
        save(&format!("ambient-occlusion-{name}"), &on);
        // The scene too, for the guide's picture (docs/guide/shadows.md).
        let scene_file = common::output_dir().join(format!("ambient-occlusion-{name}.json"));
        let _ = std::fs::write(scene_file, scene.to_json());
        let (w, h) = (scene.image.width as usize, scene.image.height as usize);
        let glyphs = glyphs_of(&sets);
        let hits = hits(&scene, &glyphs);
        // The ambient term.
        let term = |c: usize, _: f64| f64::from(BASE[c]) * f64::from(ambient);
        let (mut compared, mut occluded, mut wrong) = (0, 0, Vec::new());
        for j in 1..h - 1 {
            for i in 1..w - 1 {
                let k = j * w + i;
                // The pixel's rays cast from its neighbours' hits.
                let share = |n: usize| {
                    let (g, hit, dir) = hits[n]?;
                    let (reach, pattern) = (f64::from(reach), pattern_of(k, w));
                    Some(shadow::ambient_share(
                        &glyphs[g], hit, dir, reach, pattern, &glyphs,
                    ))
                };
                let fits = |r| share_mismatches(&off, &on, k, r, term).is_empty();
                let Some(range) = share_range(share, (w, i, j), 2.0 / 16.0, fits) else {
                    continue;
                };
                compared += 1;
                occluded += usize::from(range.0 < 1.0);
                for (c, got, low, high) in share_mismatches(&off, &on, k, range, term) {
                    wrong.push((i, j, c, got, low, high));
                }
            }
        }
        eprintln!(
            "{name}: {compared} pixels, {occluded} occluded, {} wrong",
            wrong.len()
        );
        assert!(
            wrong.is_empty(),
            "{name}: {:?}",
            &wrong[..wrong.len().min(20)]
        );
        assert!(
            compared > 1000 && occluded >= 100,
            "{name}: {compared} compared, {occluded} occluded"
        );
        let brighter = (0..w * h * 4).filter(|&c| on.rgba[c] > off.rgba[c]).count();
        assert_eq!(brighter, 0, "{name}: channels brightened");
    }
}

/// A grey underlay plane at height `z` under the fibre field: 16 x 16 voxels of a smooth
/// field (no NaN), window 0 to 100.
fn underlay_below(z: f64) -> Underlay {
    let dims = [16, 16, 1];
    let values = (0..16 * 16)
        .map(|n| {
            let (i, j) = (f64::from(n % 16), f64::from(n / 16));
            (45.0 + 25.0 * (0.7 * i).sin() + 20.0 * (0.5 * j).cos()) as f32
        })
        .collect();
    let affine = glam::DMat4::from_scale_rotation_translation(
        DVec3::new(0.25, 0.25, 1.0),
        glam::DQuat::IDENTITY,
        DVec3::new(-1.875, -1.875, z),
    );
    let mut volume = UnderlayVolume::new("ramp", dims, 1, values, affine).expect("volume");
    volume.set_window(0.0, 100.0).expect("window");
    Underlay {
        volume: std::sync::Arc::new(volume),
        planes: vec![UnderlayPlane {
            origin: DVec3::new(-1.9, -1.9, z),
            u: DVec3::new(3.8, 0.0, 0.0),
            v: DVec3::new(0.0, 3.8, 0.0),
            sample_offset: DVec3::ZERO,
        }],
    }
}

/// Shadows and occlusion fall on the underlay: under the fibre field lit from the side,
/// every underlay pixel away from shadow edges keeps the share of its colour that the
/// float64 reference gives it (ambient * occlusion share + (1 - ambient) * lit share,
/// the plane a matte surface facing the light), within the 8-bit rounding; unshadowed
/// pixels keep their colour bit for bit, no channel brightens and the depth map does not
/// change.
#[test]
fn the_underlay_receives_shadows_and_occlusion() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (scene, light) = fibre_field(128);
    let underlay = underlay_below(-0.55);
    let plane = &underlay.planes[0];
    let normal = plane.u.cross(plane.v).normalize();
    let ambient = 0.4;
    for (name, shadows, reach) in [
        ("hard", Shadows::Hard, None),
        ("occlusion", Shadows::Off, Some(1.0f32)),
    ] {
        let (sets, off, on) = render_changed(
            &gpu,
            &mut renderer,
            (&scene, Some(&underlay)),
            light,
            ambient,
            |s| {
                s.shadows = shadows;
                if let Some(reach) = reach {
                    s.ambient_occlusion = AmbientOcclusion::On { reach };
                }
            },
        );
        save(&format!("underlay-shadows-{name}-off"), &off);
        save(&format!("underlay-shadows-{name}"), &on);
        let (w, h) = (scene.image.width as usize, scene.image.height as usize);
        let glyphs = glyphs_of(&sets);
        // Without shadows no ray goes towards the light.
        let rays = u32::from(shadows == Shadows::Hard);
        let lighting = (light.normalize(), rays, 0.0);
        // One occlusion ray's step of the share, or any step of the hard shadows.
        let step = reach.map_or(0.0, |_| f64::from(ambient) / 16.0);
        // Per pixel: the point of an underlay pixel (the plane nearer than every glyph)
        // and its ray's direction.
        let mut points = Vec::with_capacity(w * h);
        for j in 0..h as u32 {
            for i in 0..w as u32 {
                let ray = scene.camera.ray(i, j, w as u32, h as u32);
                let on_plane = plane.intersect(&ray).filter(|&t| {
                    underlay.volume.shade(ray.origin + t * ray.dir).is_some()
                        && glyphs
                            .iter()
                            .all(|g| first_hit(&ray, g).is_none_or(|u| u > t))
                });
                points.push(on_plane.map(|t| (ray.origin + t * ray.dir, ray.dir)));
            }
        }
        // The colour's share: full * (1 - (1 - share)).
        let term = |_: usize, full: f64| full;
        let (mut compared, mut darkened, mut wrong) = (0, 0, Vec::new());
        for j in 1..h - 1 {
            for i in 1..w - 1 {
                let k = j * w + i;
                // The share of pixel n's point with the rays of pixel k.
                let share = |n: usize| {
                    let (point, dir) = points[n]?;
                    let (reach, ambient) = (reach.map(f64::from), f64::from(ambient));
                    let at = (point, normal, dir);
                    let pattern = pattern_of(k, w);
                    Some(shadow::plane_share(
                        at, lighting, pattern, reach, ambient, &glyphs,
                    ))
                };
                // Hard shadows' one ray is every pixel's: those are held to the range of
                // the neighbourhood, as before; occlusion first to the pixel's own share.
                let fits = |r: (f64, f64)| {
                    let same = off.rgba[4 * k..4 * k + 4] == on.rgba[4 * k..4 * k + 4];
                    reach.is_some()
                        && if r.0 >= 1.0 {
                            same
                        } else {
                            share_mismatches(&off, &on, k, r, term).is_empty()
                        }
                };
                let Some((lo, hi)) = share_range(share, (w, i, j), 2.0 * step, fits) else {
                    continue;
                };
                compared += 1;
                if lo >= 1.0 {
                    if off.rgba[4 * k..4 * k + 4] != on.rgba[4 * k..4 * k + 4] {
                        wrong.push((i, j, 4, f64::from(on.rgba[4 * k]), 1.0, 1.0));
                    }
                    continue;
                }
                darkened += 1;
                for (c, got, low, high) in share_mismatches(&off, &on, k, (lo, hi), term) {
                    wrong.push((i, j, c, got, low, high));
                }
            }
        }
        eprintln!(
            "underlay, {name}: {compared} pixels, {darkened} darkened, {} wrong",
            wrong.len()
        );
        assert!(
            wrong.is_empty(),
            "underlay, {name}: {:?}",
            &wrong[..wrong.len().min(20)]
        );
        assert!(
            compared > 2000 && darkened >= 300,
            "underlay, {name}: {compared} compared, {darkened} darkened"
        );
        let brighter = (0..w * h * 4).filter(|&c| on.rgba[c] > off.rgba[c]).count();
        assert_eq!(brighter, 0, "underlay, {name}: channels brightened");
    }
}

/// A wide flat glyph (radius 3) above a uniform grey underlay plane, lit obliquely (from
/// -x, 27 degrees off the vertical), and an orthographic camera looking straight down at
/// the edge of its shadow, 96 x 24 pixels over 1.2 x 0.3 world units: a soft light of 15
/// degrees makes a penumbra about 70 pixels wide (the glyph's rim is a lens, whose upper
/// face reaches further out than its edge) that runs across the columns, the umbra at
/// the left and full light at the right. The shadow's edge is a circle of radius 3,
/// 240 pixels: over the image's 24 rows it is a straight line to a third of a pixel, its
/// normal turned by at most 3 degrees.
fn wide_disc_over_plane() -> (Scene, Underlay, DVec3) {
    let disc = glyph_set(
        symmetric(2),
        vec![DVec3::ZERO],
        3.0,
        vec![vec![1.0, 0.0, 0.0, 1.0, 0.0, 0.02]],
    );
    let mut scene = glyphcast::accuracy::suite::scene(vec![disc], DVec3::ZERO, 96);
    scene.image.height = 24;
    scene.camera = Camera {
        projection: glyphcast::camera::Projection::Orthographic { height: 0.3 },
        eye: DVec3::new(3.6, 0.0, 3.0),
        target: DVec3::new(3.6, 0.0, -1.0),
        up: DVec3::Y,
    };
    let z = -1.0;
    let affine = glam::DMat4::from_translation(DVec3::new(0.0, -4.0, z));
    let mut volume =
        UnderlayVolume::new("grey", [8, 8, 1], 1, vec![70.0; 64], affine).expect("volume");
    volume.set_window(0.0, 100.0).expect("window");
    let underlay = Underlay {
        volume: std::sync::Arc::new(volume),
        planes: vec![UnderlayPlane {
            origin: DVec3::new(2.5, -1.0, z),
            u: DVec3::new(2.5, 0.0, 0.0),
            v: DVec3::new(0.0, 2.0, 0.0),
            sample_offset: DVec3::ZERO,
        }],
    };
    (scene, underlay, DVec3::new(-0.5, 0.0, 1.0))
}

/// A soft shadow's penumbra is smooth: across the penumbra of a straight shadow edge
/// (`wide_disc_over_plane`), the underlay's share of its colour (linear, each column's
/// mean over the 24 rows, so along the edge) changes from one column to the next by at
/// most 1/12 of its range, umbra to full light. A pattern of rays that every pixel
/// shares crosses the edge one sample row at a time and leaves steps of two or three of
/// its 16 rays (the rings of the penumbra); a pattern turned per pixel leaves fine noise
/// that the mean along the edge evens out.
#[test]
fn soft_penumbrae_change_in_small_steps() {
    let gpu = common::gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (scene, underlay, light) = wide_disc_over_plane();
    let ambient = 0.4;
    let soft = Shadows::Soft { radius_deg: 15.0 };
    let (_, off, on) = render_changed(
        &gpu,
        &mut renderer,
        (&scene, Some(&underlay)),
        light,
        ambient,
        |s| s.shadows = soft,
    );
    save("penumbra-off", &off);
    save("penumbra-soft", &on);
    let (w, h) = (scene.image.width as usize, scene.image.height as usize);
    let share = |k: usize| {
        let full = f64::from(srgb_to_linear(off.rgba[4 * k]));
        assert!(full > 0.1, "pixel {k} is not the underlay's");
        f64::from(srgb_to_linear(on.rgba[4 * k])) / full
    };
    let profile: Vec<f64> = (0..w)
        .map(|i| (0..h).map(|j| share(j * w + i)).sum::<f64>() / h as f64)
        .collect();
    let steps: Vec<f64> = profile.windows(2).map(|p| (p[1] - p[0]).abs()).collect();
    let range = 1.0 - f64::from(ambient);
    let largest = steps.iter().cloned().fold(0.0, f64::max);
    let row: Vec<String> = profile.iter().map(|v| format!("{v:.3}")).collect();
    eprintln!(
        "penumbra: shares {}; largest step {:.3} of the range",
        row.join(" "),
        largest / range
    );
    // The image spans the penumbra: the umbra at the left (the ambient share, within the
    // 8-bit rounding), (nearly) full light at the right, where the penumbra's tail leaves
    // a pixel a ray blocked now and then, and 40 columns or more in between.
    assert!(
        profile[..3].iter().all(|&v| v < f64::from(ambient) + 0.01),
        "{row:?}"
    );
    assert!(profile[w - 3..].iter().all(|&v| v > 0.98), "{row:?}");
    let between = profile
        .iter()
        .filter(|&&v| v > f64::from(ambient) + 0.02 && v < 0.97)
        .count();
    assert!(between >= 40, "{between} columns in the penumbra");
    assert!(
        largest <= range / 12.0,
        "a step of {:.3} of the penumbra's range (at most 1/12)",
        largest / range
    );
}

/// Through the command line: `--shadows` alone on the sphere above the flat glyph leaves
/// the depth map unchanged, darkens at least 0.5 % of the covered pixels and brightens
/// none.
#[test]
fn the_shadows_flag_darkens_and_keeps_the_depth_map() {
    let dir = fresh_dir("shadows-cli");
    let (scene, light) = sphere_above_flat(160);
    let scene_file = dir.join("scene.json");
    std::fs::write(&scene_file, scene.to_json()).expect("scene");
    let [x, y, z] = view_light(&scene.camera, light);
    let light = format!("{x},{y},{z}");
    let render = |name: &str, extra: &[&str]| {
        let png = dir.join(format!("{name}.png"));
        let npy = dir.join(format!("{name}.npy"));
        let mut args = vec![
            "render",
            scene_file.to_str().expect("utf-8"),
            "--light",
            &light,
            "-o",
            png.to_str().expect("utf-8"),
            "--depth-out",
            npy.to_str().expect("utf-8"),
        ];
        args.extend_from_slice(extra);
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let (_, _, rgba) = read_png_rgba8(&png).expect("png");
        (rgba, std::fs::read(&npy).expect("npy"))
    };
    let (plain, plain_depth) = render("plain", &[]);
    let (shadowed, shadowed_depth) = render("shadowed", &["--shadows"]);
    assert!(plain_depth == shadowed_depth, "the depth map changed");
    let covered = plain.chunks(4).filter(|p| p[3] == 255).count();
    let darker = plain
        .chunks(4)
        .zip(shadowed.chunks(4))
        .filter(|(a, b)| a[3] == 255 && (0..3).any(|c| b[c] < a[c]))
        .count();
    let brighter = plain
        .chunks(4)
        .zip(shadowed.chunks(4))
        .filter(|(a, b)| (0..4).any(|c| b[c] > a[c]))
        .count();
    eprintln!("{darker} of {covered} covered pixels darker, {brighter} brighter");
    assert!(covered > 2000);
    assert!(
        darker as f64 >= 0.005 * covered as f64,
        "{darker} of {covered}"
    );
    assert_eq!(brighter, 0);
    // soft:RADIUS through the flag, too.
    let (soft, soft_depth) = render("soft", &["--shadows", "soft:6"]);
    assert!(soft_depth == plain_depth);
    assert!(soft != plain && soft != shadowed);
    // --ambient-occlusion alone darkens the flat glyph under the sphere, keeps the depth
    // map and brightens nothing; with --shadows both take light away.
    let (occluded, occluded_depth) = render("occluded", &["--ambient-occlusion"]);
    assert!(occluded_depth == plain_depth);
    let changed = |image: &[u8], darker: bool| {
        plain
            .chunks(4)
            .zip(image.chunks(4))
            .filter(|(a, b)| (0..4).any(|c| if darker { b[c] < a[c] } else { b[c] > a[c] }))
            .count()
    };
    eprintln!("--ambient-occlusion: {} darker", changed(&occluded, true));
    assert!(changed(&occluded, true) as f64 >= 0.005 * covered as f64);
    assert_eq!(changed(&occluded, false), 0);
    let (both, both_depth) = render("both", &["--ambient-occlusion", "2", "--shadows"]);
    assert!(both_depth == plain_depth);
    assert!(changed(&both, true) > changed(&shadowed, true));
    assert_eq!(changed(&both, false), 0);
}

/// Bad values and methods without shadow or occlusion rays are usage errors naming the
/// setting.
#[test]
fn bad_shadow_values_are_usage_errors() {
    let dir = fresh_dir("shadows-errors");
    let (scene, _) = sphere_above_flat(64);
    let scene_file = dir.join("scene.json");
    std::fs::write(&scene_file, scene.to_json()).expect("scene");
    let png = dir.join("out.png");
    let cases: [(&[&str], &[&str]); 8] = [
        (
            &["--shadows", "sometimes"],
            &["--shadows 'sometimes'", "soft:RADIUS"],
        ),
        (&["--shadows", "soft:0"], &["--shadows 'soft:0'", "above 0"]),
        (&["--shadows", "soft:x"], &["--shadows 'soft:x'", "degrees"]),
        (
            &["--shadows", "--method", "fixed"],
            &["--shadows", "--method exact"],
        ),
        (
            &["--ambient-occlusion", "often"],
            &["--ambient-occlusion 'often'", "reach"],
        ),
        (
            &["--ambient-occlusion", "0"],
            &["--ambient-occlusion 0", "above 0"],
        ),
        (
            &["--ambient-occlusion", "17"],
            &["--ambient-occlusion 17", "at most 16"],
        ),
        (
            &["--ambient-occlusion", "--method", "affine"],
            &["--ambient-occlusion", "--method exact"],
        ),
    ];
    for (extra, words) in cases {
        let mut args = vec!["render", scene_file.to_str().expect("utf-8"), "-o"];
        args.push(png.to_str().expect("utf-8"));
        args.extend_from_slice(extra);
        let out = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        for word in words {
            assert!(stderr.contains(word), "{extra:?}: {word:?} not in {stderr}");
        }
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// Shapes that take no shadow or occlusion rays (here the reciprocal glyph of Young's
/// modulus, written by `glyphcast stiffness`) are drawn as without them, with a note
/// saying so; polynomial glyphs get no such note.
#[test]
fn shapes_without_rays_are_drawn_without_them_and_say_so() {
    let dir = fresh_dir("shadows-shapes");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let copper = root.join("examples/stiffness/copper.txt");
    let scene = dir.join("young.json");
    let out = glyphcast(&[
        "stiffness",
        copper.to_str().expect("utf-8"),
        "--surface",
        "young",
        "-o",
        scene.to_str().expect("utf-8"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let render = |name: &str, extra: &[&str]| {
        let png = dir.join(format!("{name}.png"));
        let mut args = vec!["render", scene.to_str().expect("utf-8"), "--width", "96"];
        args.extend(["--height", "96", "-o", png.to_str().expect("utf-8")]);
        args.extend_from_slice(extra);
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        (std::fs::read(&png).expect("png"), stderr)
    };
    let (plain, quiet) = render("plain", &[]);
    assert!(!quiet.contains("note:"), "{quiet}");
    for flag in ["--shadows", "--ambient-occlusion"] {
        let (image, stderr) = render(flag.trim_start_matches('-'), &[flag]);
        assert!(image == plain, "{flag} changed the reciprocal glyph");
        assert!(
            stderr.contains("note: glyphs of shape reciprocal receive and cast no shadows"),
            "{flag}: {stderr}"
        );
    }
}
