//! Streamlines drawn as tubes with the glyphs: the tubes of bent, crossing and degenerate
//! streamlines against the float64 capsule reference (no hole, no false hit, the depth
//! to 1e-4), tubes and glyphs hiding each other in one depth buffer on the fragment and
//! the compute paths, and `render --tracks` on a real fODF volume, its refusals included.
use crate::common::{self, expect_failure, expect_usage_failure, fresh_dir, glyphcast, gpu};
use crate::peaks::{capsule_depth, compare, nearer, render_alone};
use glam::DVec3;
use glyphcast::camera::{Camera, Projection};
use glyphcast::demo::{direction, fibre_tensor, glyph_set, symmetric};
use glyphcast::glyph::reference::reference_depth;
use glyphcast::render::glyph_data::prepare_scene;
use glyphcast::render::headless::{FrameView, HeadlessRenderer};
use glyphcast::render::peaks::PeakSet;
use glyphcast::render::{RenderPath, RenderSettings};
use glyphcast::scene::{ImageSize, Scene};
use glyphcast_dmri::io::tracks::Tractogram;
use glyphcast_dmri::volume::{TrackStyle, tube_set};
use std::path::Path;

/// Streamlines that test the joints: a zigzag with sharp (150 degree) bends, a helix of
/// short steps, two lines that cross, a streamline with a repeated point and a step of
/// 1e-6, and a one-point streamline; within x, y in [-1.8, 1.8], z in [-0.6, 0.6].
fn test_streamlines() -> Tractogram {
    let mut lines: Vec<Vec<[f32; 3]>> = Vec::new();
    lines.push(
        (0..7)
            .map(|k| {
                [
                    -1.6 + 0.5 * k as f32,
                    if k % 2 == 0 { 1.2 } else { 0.9 },
                    0.2,
                ]
            })
            .collect(),
    );
    lines.push(
        (0..60)
            .map(|k| {
                let a = 0.25 * k as f32;
                [
                    0.5 * a.cos() - 0.6,
                    0.5 * a.sin() - 0.7,
                    -0.6 + 0.02 * k as f32,
                ]
            })
            .collect(),
    );
    lines.push(vec![[-1.5, -1.5, 0.0], [1.5, 1.5, 0.0]]);
    lines.push(vec![[-1.5, 1.5, 0.3], [1.5, -1.5, -0.3]]);
    lines.push(vec![
        [0.8, -1.4, 0.1],
        [1.2, -1.0, 0.1],
        [1.2, -1.0, 0.1],
        [1.200001, -1.0, 0.1],
        [1.6, -0.4, 0.4],
    ]);
    lines.push(vec![[1.4, 1.4, 0.5]]);
    let mut tractogram = Tractogram::default();
    for line in lines {
        tractogram.offsets.push(tractogram.points.len() as u64);
        tractogram.points.extend(line);
    }
    tractogram
}

fn camera(projection: Projection, eye: DVec3) -> Camera {
    Camera {
        projection,
        eye,
        target: DVec3::ZERO,
        up: DVec3::Y,
    }
}

fn tubes(radius: f64) -> PeakSet {
    let style = TrackStyle {
        radius,
        ..TrackStyle::default()
    };
    tube_set(&test_streamlines(), &style)
}

/// The tubes alone, in an orthographic and a perspective view, on the fragment path:
/// every pixel outside the one-pixel silhouette band covered exactly where the float64
/// reference (the nearest capsule entry) has a hit, at its depth within 1e-4; the joints
/// of the zigzag and the helix, the crossing and the degenerate steps included.
#[test]
fn tubes_match_the_float64_reference() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let tubes = tubes(0.06);
    let (w, h) = (160, 144);
    let eye = DVec3::new(0.9, 1.3, 6.0);
    for camera in [
        camera(Projection::Orthographic { height: 4.0 }, eye),
        camera(Projection::Perspective { fov_y_deg: 42.0 }, eye),
    ] {
        let (_, _, a) = render_alone(&gpu, &mut renderer, &tubes, &camera, (w, h));
        assert!(a.compared > 500, "{a:?}: too few tube pixels to judge");
        assert_eq!(a.coverage_errors, 0, "holes or false hits: {a:?}");
        assert!(a.worst_depth <= 1e-4, "{a:?}");
    }
}

/// Four fODF glyphs in a row, seen orthographically from the front and a little above,
/// and streamlines along the row in front of (z 0.35), through (0) and behind (-0.35)
/// the glyphs' centres, and one that dives through them: the camera, the image size, the
/// scene, its glyph data and the streamlines.
fn glyph_row() -> (
    Camera,
    (u32, u32),
    Vec<glyphcast::render::glyph_data::GlyphSetData>,
    Tractogram,
) {
    let centers: Vec<DVec3> = (0..4)
        .map(|n| DVec3::new(n as f64 - 1.5, 0.0, 0.0))
        .collect();
    let tensors: Vec<Vec<f64>> = (0..4)
        .map(|n| {
            let fibres = [
                (direction(30.0 * n as f64, 15.0), 1.0),
                (direction(30.0 * n as f64 + 90.0, -10.0), 0.8),
            ];
            fibre_tensor(6, &fibres)
        })
        .collect();
    let (w, h) = (240, 192);
    let camera = camera(
        Projection::Orthographic { height: 3.2 },
        DVec3::new(0.4, 0.7, 6.0),
    );
    let scene = Scene {
        glyph_sets: vec![glyph_set(symmetric(6), centers, 0.5, tensors)],
        camera,
        image: ImageSize {
            width: w,
            height: h,
        },
    };
    let sets = prepare_scene(&scene, 0.0).expect("glyphs");
    // Streamlines along x at heights in front of (z 0.35), through (0) and behind
    // (-0.35) the glyphs' centres, and one that dives through them.
    let mut tractogram = Tractogram::default();
    for (y, z0, z1) in [
        (0.25, 0.35, 0.35),
        (-0.05, 0.0, 0.0),
        (-0.3, -0.35, -0.35),
        (0.05, 0.5, -0.5),
    ] {
        tractogram.offsets.push(tractogram.points.len() as u64);
        tractogram.points.extend((0..41).map(|k| {
            let s = k as f32 / 40.0;
            [-2.2 + 4.4 * s, y, z0 + (z1 - z0) * s]
        }));
    }
    (camera, (w, h), sets, tractogram)
}

/// Tubes passing in front of, through and behind four fODF glyphs, on the fragment and
/// the compute paths: outside the silhouette bands every pixel shows the nearer of the
/// two float64 references, at its depth, and each wins hundreds of pixels.
#[test]
fn tubes_and_glyphs_hide_each_other_on_both_paths() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (camera, (w, h), sets, tractogram) = glyph_row();
    let tubes = tube_set(
        &tractogram,
        &TrackStyle {
            radius: 0.05,
            ..TrackStyle::default()
        },
    );
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    let glyphs = reference_depth(&world, &camera, w, h);
    let capsules = capsule_depth(&tubes, &camera, w, h);
    let wu = w as usize;
    let n = nearer(&glyphs, &capsules, (wu, h as usize));
    let band = |x, y| n.band[y * wu + x];
    let (tubes_win, glyphs_win) = n.won;
    eprintln!("where both are hit: tubes nearer at {tubes_win}, glyphs at {glyphs_win}");
    assert!(
        tubes_win > 200 && glyphs_win > 200,
        "{tubes_win} / {glyphs_win}"
    );
    for path in [RenderPath::Fragment, RenderPath::Compute] {
        let settings = RenderSettings {
            path,
            ..RenderSettings::default()
        };
        let view = FrameView::new(&camera, w, h).with_peaks(Some(&tubes));
        let image = renderer
            .render_view(&gpu, &sets, &view, &settings)
            .expect("rendering tubes and glyphs");
        let a = compare(&image, &n.depth, &band);
        eprintln!("{path:?}: {a:?}");
        assert!(a.compared > 3000, "{path:?}: {a:?}");
        assert_eq!(a.coverage_errors, 0, "{path:?}: {a:?}");
        assert!(a.worst_depth <= 1e-4, "{path:?}: {a:?}");
    }
}

/// Writes `tractogram` as an MRtrix .tck (the library's writer: float32 little-endian,
/// NaN between streamlines, Inf at the end, as MRtrix's own writer lays it out).
pub(crate) fn write_tck(path: &Path, tractogram: &Tractogram) {
    glyphcast_dmri::io::tracks::tck::write_tck(tractogram, path).expect("writing the .tck");
}

/// `render --sh` of the DIPY CSD fit with `--tracks` (streamlines through the volume in
/// scanner millimetres) on the default axial slice, with a slab: the image differs from
/// the one without tracks, tube colours are drawn, and a smaller slab draws fewer tube
/// pixels; the track options without --tracks, a bad radius and a file that is not a
/// tractogram are refused naming the option or the file.
#[test]
fn render_draws_tracks_over_the_fodf_slice() {
    let dir = fresh_dir("render-tracks");
    let fod = common::dipy_csd_fit();
    // Through the volume's world box (x 2..20, y 3..25, z 12..25 mm): lines along x at
    // the height of the middle axial slices, and one steep across them.
    let mut tractogram = Tractogram::default();
    for (y, z0, z1) in [(10.0, 18.0, 18.5), (16.0, 19.0, 18.0), (20.0, 12.0, 25.0)] {
        tractogram.offsets.push(tractogram.points.len() as u64);
        tractogram.points.extend((0..31).map(|k| {
            let s = k as f32 / 30.0;
            [1.0 + 20.0 * s, y, z0 + (z1 - z0) * s]
        }));
    }
    let tck = dir.join("synthetic.tck");
    write_tck(&tck, &tractogram);
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render".to_owned(),
            "--sh".to_owned(),
            fod.display().to_string(),
            "--width".to_owned(),
            "200".to_owned(),
            "-o".to_owned(),
            out.display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        let run = glyphcast(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        glyphcast::io::png::read_png_rgba8(&out).expect("the PNG").2
    };
    let plain = render("plain.png", &[]);
    let tck_arg = tck.display().to_string();
    let wide = render(
        "wide.png",
        &[
            "--tracks",
            &tck_arg,
            "--slab",
            "20",
            "--tracks-radius",
            "0.4",
        ],
    );
    let thin = render(
        "thin.png",
        &[
            "--tracks",
            &tck_arg,
            "--slab",
            "0.5",
            "--tracks-radius",
            "0.4",
        ],
    );
    let changed = |a: &[u8], b: &[u8]| a.chunks(4).zip(b.chunks(4)).filter(|(p, q)| p != q).count();
    let (wide_changed, thin_changed) = (changed(&plain, &wide), changed(&plain, &thin));
    eprintln!("pixels changed by the tubes: slab 20 mm {wide_changed}, slab 0.5 mm {thin_changed}");
    assert!(wide_changed > 300, "{wide_changed}");
    assert!(
        thin_changed < wide_changed,
        "{thin_changed} >= {wide_changed}"
    );
    // Refusals: an option without --tracks, a bad radius (usage, exit 2); a file that is
    // not a tractogram (input, exit 1), named; nothing written.
    let refused = fresh_dir("render-tracks-refused");
    let fod_arg = fod.display().to_string();
    let out = refused.join("refused.png").display().to_string();
    let base = ["render", "--sh", fod_arg.as_str(), "-o", out.as_str()];
    let alone = [&base[..], &["--slab", "2"]].concat();
    expect_usage_failure(&alone, &refused, &["--slab", "--tracks"]);
    let radius = [
        &base[..],
        &["--tracks", tck_arg.as_str(), "--tracks-radius", "-1"],
    ]
    .concat();
    expect_usage_failure(&radius, &refused, &["--tracks-radius"]);
    let not_tracks = dir.join("not.tck");
    std::fs::write(&not_tracks, b"hello\n").expect("writing");
    let bad_arg = not_tracks.display().to_string();
    let bad = [&base[..], &["--tracks", bad_arg.as_str()]].concat();
    expect_failure(&bad, &refused, &["not.tck"]);
    // A value per point: nibabel's complex.trk stores fa (one number a point) and
    // colors (three); the map is printed; another value, a value of three numbers and a
    // file without values are refused naming the option and the file.
    let complex = common::test_data("tracks", "complex_big_endian.trk")
        .display()
        .to_string();
    let fa_png = dir.join("fa.png").display().to_string();
    let scalar = [
        &base[..2],
        &[
            fod_arg.as_str(),
            "-o",
            fa_png.as_str(),
            "--tracks",
            complex.as_str(),
            "--tracks-color",
            "scalar:fa",
        ],
    ]
    .concat();
    let run = glyphcast(&scalar);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("streamlines coloured by fa: viridis from 0.2"),
        "{stderr}"
    );
    let complex_arg = complex.as_str();
    for (color, words) in [
        (
            "scalar:md",
            &["--tracks-color", "complex_big_endian.trk", "colors, fa"][..],
        ),
        (
            "scalar:colors",
            &["--tracks-color", "3 numbers per point"][..],
        ),
    ] {
        let args = [
            &base[..],
            &["--tracks", complex_arg, "--tracks-color", color],
        ]
        .concat();
        expect_usage_failure(&args, &refused, words);
    }
    let args = [
        &base[..],
        &["--tracks", tck_arg.as_str(), "--tracks-color", "scalar"],
    ]
    .concat();
    expect_usage_failure(
        &args,
        &refused,
        &["--tracks-color", "stores no value per point"],
    );
}

/// `bench --workload tracks:...` measures the tubes and, with `--save-tracks`, writes the
/// streamlines it drew as a `.tck` that the reader takes back: whole in 3D (every
/// streamline, every point), and only the parts within the 5 mm slab. `--save-scene`
/// writes its camera. `--save-tracks` without a tracks workload, or under another name
/// than `.tck`, is refused naming it.
#[test]
fn bench_writes_the_tracks_workload_it_measures() {
    let dir = fresh_dir("bench-tracks");
    let bench = |spec: &str, name: &str| {
        let tck = dir.join(format!("{name}.tck"));
        let scene = dir.join(format!("{name}.json"));
        let (tck_arg, scene_arg) = (tck.display().to_string(), scene.display().to_string());
        let run = glyphcast(&[
            "bench",
            "--workload",
            spec,
            "--width",
            "96",
            "--height",
            "64",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--save-tracks",
            &tck_arg,
            "--save-scene",
            &scene_arg,
        ]);
        let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
        assert!(
            run.status.success(),
            "{stdout}{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let tractogram = glyphcast_dmri::io::tracks::read_tractogram(&tck).expect("the .tck");
        let scene = glyphcast::scene::Scene::load(&scene).expect("the scene");
        assert!(scene.glyph_sets.is_empty());
        (tractogram, stdout)
    };
    let (whole, stdout) = bench("tracks:30:12", "whole");
    assert_eq!(whole.len(), 30);
    assert!(whole.streamlines().all(|line| line.len() == 12));
    assert!(stdout.contains("330 segments"), "{stdout}");
    let (slab, stdout) = bench("tracks:400:40:slab", "slab");
    let segments: usize = slab.streamlines().map(|line| line.len() - 1).sum();
    assert!(
        segments > 0 && stdout.contains(&format!("{segments} segments")),
        "{stdout}"
    );
    assert!(slab.points.iter().all(|p| p[2].abs() <= 2.5 + 1e-4));
    // Refusals, nothing written.
    let refused = fresh_dir("bench-tracks-refused");
    let out = refused.join("t.tck").display().to_string();
    expect_usage_failure(
        &["bench", "--workload", "grid:4:4", "--save-tracks", &out],
        &refused,
        &["--save-tracks", "tracks"],
    );
    let png = refused.join("t.png").display().to_string();
    expect_usage_failure(
        &["bench", "--workload", "tracks:3:4", "--save-tracks", &png],
        &refused,
        &["--save-tracks", "t.png"],
    );
}

/// The ray's point nearest the segment a-b (a point of the segment, clamped to it): its
/// distance from the ray, and the ray parameter of the ray's point nearest it.
fn ray_to_segment(ray: &glyphcast::camera::Ray, a: DVec3, b: DVec3) -> (f64, f64) {
    let across = |v: DVec3| v - v.dot(ray.dir) * ray.dir;
    let (w0, e) = (a - ray.origin, b - a);
    let (pw, pe) = (across(w0), across(e));
    let s = if pe.length_squared() > 1e-24 {
        (-pw.dot(pe) / pe.length_squared()).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let p = w0 + s * e;
    (across(p).length(), p.dot(ray.dir))
}

/// Streamlines drawn as lines (`--tracks-style lines`), alone, orthographic and
/// perspective: every covered pixel's ray passes within the line's half width (at least
/// half a pixel) and a pixel of a streamline's axis, at the ray distance of its nearest
/// approach to such a segment (within 1e-3 of the scene's 4 units); no gap: near every
/// point along every segment a pixel is covered; each streamline's own colour, unlit.
#[test]
fn lines_cover_their_streamlines_at_the_axis_depth() {
    use glyphcast_dmri::volume::{TrackShape, TracksColor};
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let radius = 0.01;
    let style = TrackStyle {
        radius,
        shape: TrackShape::Lines,
        color: TracksColor::Uniform([1.0, 0.0, 1.0]),
        ..TrackStyle::default()
    };
    let lines = tube_set(&test_streamlines(), &style);
    assert!(lines.segments.is_empty() && lines.lines.len() > 60);
    let (w, h) = (160, 144);
    let eye = DVec3::new(0.9, 1.3, 6.0);
    for (camera, pixel_at_unit) in [
        (camera(Projection::Orthographic { height: 4.0 }, eye), None),
        (
            camera(Projection::Perspective { fov_y_deg: 42.0 }, eye),
            Some(2.0 * 21f64.to_radians().tan() / h as f64),
        ),
    ] {
        let view = FrameView::new(&camera, w, h).with_peaks(Some(&lines));
        let image = renderer
            .render_view(&gpu, &[], &view, &RenderSettings::default())
            .expect("rendering lines");
        // World size of a pixel at ray distance t.
        let pixel = |t: f64| pixel_at_unit.map_or(4.0 / h as f64, |unit| unit * t);
        let mut covered = 0;
        for j in 0..h {
            for i in 0..w {
                let k = (j * w + i) as usize;
                let distance = image.distance[k];
                if distance.is_nan() {
                    continue;
                }
                covered += 1;
                assert_eq!(
                    &image.rgba[4 * k..4 * k + 3],
                    &[255, 0, 255],
                    "pixel {i},{j}: not the lines' own colour"
                );
                let ray = camera.ray(i, j, w, h);
                let explained = lines.lines.iter().any(|s| {
                    let (off, t) = ray_to_segment(&ray, s.capsule.a, s.capsule.b);
                    off <= radius.max(0.5 * pixel(t)) + 1.5 * pixel(t)
                        && (f64::from(distance) - t).abs() <= 1e-3
                });
                let nearest = lines
                    .lines
                    .iter()
                    .map(|s| (ray_to_segment(&ray, s.capsule.a, s.capsule.b), s.capsule))
                    .min_by(|a, b| a.0.0.total_cmp(&b.0.0));
                assert!(
                    explained,
                    "pixel {i},{j} at {distance} ({} world a pixel): no segment there; the \
                     nearest: {nearest:?}",
                    pixel(f64::from(distance))
                );
            }
        }
        // No gap: every point a quarter of the way along each segment has a covered
        // pixel within one pixel of it.
        let vp = camera.view_projection(w, h, 0.1, 100.0);
        for s in &lines.lines {
            for f in [0.25, 0.5, 0.75] {
                let p = s.capsule.a.lerp(s.capsule.b, f);
                let ndc = vp.project_point3(p);
                // Vulkan clip space: y grows downwards, as pixel rows do.
                let (x, y) = (
                    (ndc.x + 1.0) * 0.5 * w as f64,
                    (ndc.y + 1.0) * 0.5 * h as f64,
                );
                let near = (-2i64..=2).any(|dj| {
                    (-2i64..=2).any(|di| {
                        let (i, j) = (x.floor() as i64 + di, y.floor() as i64 + dj);
                        let inside = (0..w as i64).contains(&i) && (0..h as i64).contains(&j);
                        inside && {
                            let ray = camera.ray(i as u32, j as u32, w, h);
                            let (off, _) = ray_to_segment(&ray, p, p);
                            !image.distance[(j * w as i64 + i) as usize].is_nan()
                                && off <= 1.0 * pixel((p - ray.origin).length())
                        }
                    })
                });
                assert!(near, "a gap at {p} ({x:.1}, {y:.1})");
            }
        }
        eprintln!("{:?}: {covered} line pixels", camera.projection);
        assert!(covered > 400, "{covered}");
    }
}

/// Lines passing in front of, through and behind four fODF glyphs, on the fragment and
/// the compute paths: where a line's axis is nearer than the glyph's float64 surface (by
/// more than two pixels' depth) the pixel shows the line, where it is farther the glyph;
/// each wins hundreds of pixels, none is wrong. The glyphs' silhouette band and the
/// lines' edges (a pixel either side of the half width) are left out.
#[test]
fn lines_and_glyphs_hide_each_other_on_both_paths() {
    use glyphcast_dmri::volume::{TrackShape, TracksColor};
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
    let (camera, (w, h), sets, tractogram) = glyph_row();
    let radius = 0.05;
    let lines = tube_set(
        &tractogram,
        &TrackStyle {
            radius,
            shape: TrackShape::Lines,
            color: TracksColor::Uniform([1.0, 0.0, 1.0]),
            ..TrackStyle::default()
        },
    );
    let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
    let glyphs = reference_depth(&world, &camera, w, h);
    let pixel = 3.2 / h as f64;
    let wu = w as usize;
    let glyph_cover: Vec<bool> = glyphs.iter().map(|d| !d.is_nan()).collect();
    // Per pixel, where the lines' centres pass: the nearest axis distance of a segment
    // whose axis is within the half width less a pixel of the ray; None where no line is
    // surely drawn, and pixels at a line's edge are left out.
    let mut expected = vec![None; wu * h as usize];
    let mut edge = vec![false; wu * h as usize];
    for j in 0..h {
        for i in 0..w {
            let ray = camera.ray(i, j, w, h);
            let k = j as usize * wu + i as usize;
            for s in &lines.lines {
                let (off, t) = ray_to_segment(&ray, s.capsule.a, s.capsule.b);
                let half = radius.max(0.5 * pixel);
                if off <= half - 0.5 * pixel {
                    expected[k] = Some(expected[k].map_or(t, |e: f64| e.min(t)));
                } else if off <= half + 1.5 * pixel {
                    edge[k] = true;
                }
            }
        }
    }
    for path in [RenderPath::Fragment, RenderPath::Compute] {
        let settings = RenderSettings {
            path,
            ..RenderSettings::default()
        };
        let view = FrameView::new(&camera, w, h).with_peaks(Some(&lines));
        let image = renderer
            .render_view(&gpu, &sets, &view, &settings)
            .expect("rendering lines and glyphs");
        let (mut lines_won, mut glyphs_won, mut wrong) = (0, 0, 0);
        for y in 0..h as usize {
            for x in 0..wu {
                let k = y * wu + x;
                let (Some(line), false) = (expected[k], edge[k]) else {
                    continue;
                };
                let glyph = glyphs[k];
                if glyph.is_nan() || crate::peaks::in_band(&glyph_cover, wu, h as usize, x, y) {
                    continue;
                }
                let magenta = image.rgba[4 * k..4 * k + 3] == [255, 0, 255];
                if line < glyph - 2.0 * pixel {
                    lines_won += 1;
                    wrong += usize::from(!magenta);
                } else if line > glyph + 2.0 * pixel {
                    glyphs_won += 1;
                    wrong += usize::from(magenta);
                }
            }
        }
        eprintln!("{path:?}: lines in front at {lines_won}, glyphs at {glyphs_won}, {wrong} wrong");
        assert!(
            lines_won > 100 && glyphs_won > 100,
            "{lines_won} / {glyphs_won}"
        );
        assert_eq!(wrong, 0);
    }
}
