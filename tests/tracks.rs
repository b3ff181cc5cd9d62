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

/// Tubes passing in front of, through and behind four fODF glyphs, on the fragment and
/// the compute paths: outside the silhouette bands every pixel shows the nearer of the
/// two float64 references, at its depth, and each wins hundreds of pixels.
#[test]
fn tubes_and_glyphs_hide_each_other_on_both_paths() {
    let gpu = gpu();
    let mut renderer = HeadlessRenderer::new(&gpu).expect("renderer");
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

/// Writes `tractogram` as an MRtrix .tck (float32 little-endian, NaN between streamlines,
/// Inf at the end), as MRtrix's own writer lays it out.
pub(crate) fn write_tck(path: &Path, tractogram: &Tractogram) {
    let mut header = format!(
        "mrtrix tracks\ncount: {}\ndatatype: Float32LE\nfile: . ",
        tractogram.len()
    );
    let offset = header.len() + 16;
    header.push_str(&format!("{offset}\nEND\n"));
    let mut bytes = header.into_bytes();
    bytes.resize(offset, 0);
    for line in tractogram.streamlines() {
        for p in line {
            for v in p {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        for _ in 0..3 {
            bytes.extend_from_slice(&f32::NAN.to_le_bytes());
        }
    }
    for _ in 0..3 {
        bytes.extend_from_slice(&f32::INFINITY.to_le_bytes());
    }
    std::fs::write(path, bytes).expect("writing the .tck");
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
}
