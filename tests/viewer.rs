//! `glyphcast view` in a real window on a virtual X server (Xvfb), run by script:
//! the window shows what the headless renderer draws for the same camera, and the
//! validation layer stays clean through resizes, slice moves and setting switches.
//!
//! The Xvfb runner and the image comparisons are in tests/common/window.rs.
use crate::common;
use common::window::{
    BIN, Xvfb, assert_clean, assert_window_matches, data, differing_pixels, out, path_str, render,
};
use glyphcast::io::png::read_png_rgba8;
use std::path::{Path, PathBuf};
use std::process::Command;

#[test]
fn window_shows_what_the_headless_renderer_draws() {
    let Some(x) = Xvfb::start("window_shows_what_the_headless_renderer_draws") else {
        return;
    };
    let scene = data("tests/scenes/order4_pair.json");
    let (shot, window) = (out("pair-shot.png"), out("pair-window.png"));
    let output = x.view(&[
        &scene,
        "--width",
        "200",
        "--height",
        "150",
        "--frames",
        "3",
        "--screenshot",
        path_str(&shot),
        "--capture-window",
        path_str(&window),
    ]);
    assert_clean(&output);
    // `auto` takes the fragment path on lavapipe.
    let text = String::from_utf8_lossy(&output.stderr);
    assert!(text.contains("ray caster: fragment\n"), "{text}");
    // The screenshot is the render command's picture at the window's size: exactly.
    let expected = render(
        Path::new(&scene),
        "pair-render.png",
        &["--width", "200", "--height", "150"],
    );
    assert_eq!(differing_pixels(&shot, &expected, 0).0, 0);
    assert_window_matches(&window, &expected);
}

/// Early outs in the window (`--cull early-out`; what `occluded` takes on a device that
/// jumps over code no pixel runs): a block of 8 x 8 x 12 fODFs seen head-on, drawn in
/// one pass nearest first with each frame's known depths cleared before its rendering,
/// shows the window of `--cull off` bit for bit, and the headless renderer's picture.
#[test]
fn early_outs_in_the_window_keep_every_pixel() {
    let Some(x) = Xvfb::start("early_outs_in_the_window_keep_every_pixel") else {
        return;
    };
    let scene = out("early-outs-block.json");
    std::fs::create_dir_all(out("early-outs-bench")).expect("the bench's folder");
    let bench = Command::new(BIN)
        .args(["bench", "--workload", "block:8:8:12:8", "--width", "200"])
        .args(["--height", "150", "--frames", "1", "--warmup", "0"])
        .arg("--save-scene")
        .arg(&scene)
        .arg("--out")
        .arg(out("early-outs-bench"))
        .output()
        .expect("running glyphcast bench");
    assert!(
        bench.status.success(),
        "{}",
        String::from_utf8_lossy(&bench.stderr)
    );
    let mut windows = Vec::new();
    for cull in ["off", "early-out"] {
        let window = out(&format!("early-outs-window-{cull}.png"));
        let output = x.view(&[
            path_str(&scene),
            "--width",
            "200",
            "--height",
            "150",
            "--frames",
            "3",
            "--cull",
            cull,
            "--capture-window",
            path_str(&window),
        ]);
        assert_clean(&output);
        let text = String::from_utf8_lossy(&output.stderr);
        assert!(
            text.contains(&format!("hidden glyphs culled: {cull}\n")),
            "{cull}: {text}"
        );
        windows.push(window);
    }
    assert_eq!(
        differing_pixels(&windows[0], &windows[1], 0).0,
        0,
        "the window differs with early outs"
    );
    let expected = render(
        &scene,
        "early-outs-render.png",
        &["--width", "200", "--height", "150"],
    );
    assert_window_matches(&windows[1], &expected);
}

/// `--path compute`: the window's frames dispatch the compute ray caster before their
/// rendering and compose its outputs in it; the window and the screenshot show what
/// the fragment path draws (the sRGB bytes within one unit).
#[test]
fn the_window_draws_with_the_compute_ray_caster() {
    let Some(x) = Xvfb::start("the_window_draws_with_the_compute_ray_caster") else {
        return;
    };
    let scene = data("tests/scenes/order4_pair.json");
    let (shot, window) = (out("compute-shot.png"), out("compute-window.png"));
    let output = x.view(&[
        &scene,
        "--path",
        "compute",
        "--width",
        "200",
        "--height",
        "150",
        "--frames",
        "3",
        "--screenshot",
        path_str(&shot),
        "--capture-window",
        path_str(&window),
    ]);
    assert_clean(&output);
    let text = String::from_utf8_lossy(&output.stderr);
    assert!(text.contains("ray caster: compute\n"), "{text}");
    let expected = render(
        Path::new(&scene),
        "compute-render.png",
        &["--width", "200", "--height", "150", "--path", "fragment"],
    );
    assert_eq!(differing_pixels(&shot, &expected, 1).0, 0);
    assert_window_matches(&window, &expected);
}

/// `L` (the script's `shadows:toggle`) switches shadows on, `O` (`ambient_occlusion:toggle`)
/// ambient occlusion: the screenshot is what `render --shadows` or `render
/// --ambient-occlusion` draws, and is not the picture without them. The window casts the
/// rays in the frame's shader, the screenshot and `render` after the frame
/// (render::glyph_shadows): the window shows the same picture.
#[test]
fn the_shadows_toggle_draws_what_render_shadows_draws() {
    let Some(x) = Xvfb::start("the_shadows_toggle_draws_what_render_shadows_draws") else {
        return;
    };
    let scene = data("tests/scenes/order4_pair.json");
    let size = ["--width", "200", "--height", "150", "--light", "-1,0.3,0.4"];
    let plain = render(Path::new(&scene), "shadows-plain.png", &size);
    for (name, script, flag) in [
        ("shadows", "shadows:toggle", "--shadows"),
        (
            "occlusion",
            "ambient_occlusion:toggle",
            "--ambient-occlusion",
        ),
    ] {
        let shot = out(&format!("{name}-shot.png"));
        let window = out(&format!("{name}-window.png"));
        let mut args = vec![scene.as_str()];
        args.extend(size);
        args.extend(["--frames", "3", "--script", script]);
        args.extend(["--screenshot", path_str(&shot)]);
        args.extend(["--capture-window", path_str(&window)]);
        let output = x.view(&args);
        assert_clean(&output);
        // Polynomial glyphs take the rays: nothing to note.
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            !stderr.contains("note: glyphs of shape"),
            "{name}: {stderr}"
        );
        let mut with_rays = size.to_vec();
        with_rays.push(flag);
        let expected = render(Path::new(&scene), &format!("{name}-render.png"), &with_rays);
        assert_eq!(differing_pixels(&shot, &expected, 0).0, 0, "{name}");
        assert!(
            differing_pixels(&shot, &plain, 0).0 > 0,
            "{name}: the toggle changed nothing"
        );
        assert_window_matches(&window, &expected);
        assert!(
            differing_pixels(&window, &plain, 0).0 > 0,
            "{name}: the window shows no shadows"
        );
    }
}

/// Young's modulus is a reciprocal glyph, which takes no shadow rays: switching shadows
/// on says so, as `render` and Python do, and draws it as without them.
#[test]
fn shadows_on_a_shape_without_rays_are_noted() {
    let Some(x) = Xvfb::start("shadows_on_a_shape_without_rays_are_noted") else {
        return;
    };
    let dir = common::fresh_dir("viewer/shape-without-rays");
    let matrix = dir.join("copper.txt");
    std::fs::write(
        &matrix,
        "168.4 121.4 121.4 0 0 0\n121.4 168.4 121.4 0 0 0\n121.4 121.4 168.4 0 0 0\n\
         0 0 0 75.4 0 0\n0 0 0 0 75.4 0\n0 0 0 0 0 75.4\n",
    )
    .unwrap();
    let scene = dir.join("young.json");
    let made = common::glyphcast(&[
        "stiffness",
        path_str(&matrix),
        "--surface",
        "young",
        "-o",
        path_str(&scene),
    ]);
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    let size = ["--width", "160", "--height", "120"];
    let shot = dir.join("shot.png");
    let mut args = vec![path_str(&scene)];
    args.extend(size);
    args.extend(["--frames", "3", "--script", "shadows:toggle"]);
    args.extend(["--screenshot", path_str(&shot)]);
    let output = x.view(&args);
    assert_clean(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("note: glyphs of shape reciprocal receive and cast no shadows"),
        "{stderr}"
    );
    let plain = render(&scene, "shape-without-rays-plain.png", &size);
    assert_eq!(differing_pixels(&shot, &plain, 0).0, 0);
}

#[test]
fn scripted_session_stays_validation_clean() {
    let Some(x) = Xvfb::start("scripted_session_stays_validation_clean") else {
        return;
    };
    let volume = data("tests/data/dipy/func_coef.nii.gz");
    let (shot, window, seen) = (
        out("script-shot.png"),
        out("script-window.png"),
        out("script-scene.json"),
    );
    let script = "resize:300x200,method:fixed,step:0.05,slice:+1,color:magnitude,\
                  negative:hide,refine:bisect:2,orbit:30:10,zoom:0.8,pan:5:-3,resize:320x240";
    let mut args = vec![
        "--sh",
        &volume,
        "--basis",
        "tournier07",
        "--legacy",
        "--width",
        "240",
        "--height",
        "180",
        "--frames",
        "14",
        "--script",
        script,
    ];
    args.extend([
        "--screenshot",
        path_str(&shot),
        "--capture-window",
        path_str(&window),
        "--save-scene",
        path_str(&seen),
    ]);
    let output = x.view(&args);
    assert_clean(&output);
    let (w, h, _) = read_png_rgba8(&shot).expect("reading the screenshot");
    assert_eq!(
        (w, h),
        (320, 240),
        "the last resize is the screenshot's size"
    );

    // The slice moved from the middle (k = 2 of 4) to k = 3: the scene as shown holds
    // the glyphs the render command draws for that slice.
    let slice_3 = out("slice-3.json");
    let status = Command::new(BIN)
        .args([
            "render",
            "--sh",
            &volume,
            "--basis",
            "tournier07",
            "--legacy",
        ])
        .args(["--slice", "axial:3", "--width", "32", "--save-scene"])
        .arg(&slice_3)
        .arg("-o")
        .arg(out("slice-3.png"))
        .status()
        .expect("running glyphcast render");
    assert!(status.success());
    let centers = |path: &Path| {
        let text = std::fs::read_to_string(path).expect("reading a scene file");
        let json: serde_json::Value = serde_json::from_str(&text).expect("scene JSON");
        json["glyphs"].clone()
    };
    let (shown, expected) = (centers(&seen), centers(&slice_3));
    assert_eq!(shown[0]["centers"], expected[0]["centers"]);
    assert_eq!(shown[0]["coeffs"], expected[0]["coeffs"]);
    assert_eq!(shown[0]["negative"], "hide");

    // The scene as shown, rendered with the script's settings, is the screenshot, and
    // the window showed it too.
    let settings = [
        "--method",
        "fixed",
        "--step",
        "0.05",
        "--refine",
        "bisect:2",
        "--color",
        "magnitude",
    ];
    let expected = render(&seen, "script-render.png", &settings);
    assert_eq!(differing_pixels(&shot, &expected, 0).0, 0);
    assert_window_matches(&window, &expected);
}

#[test]
fn bad_script_is_refused_before_a_window_opens() {
    let output = Command::new(BIN)
        .args(["view", &data("tests/scenes/sphere.json"), "--frames", "2"])
        .args(["--script", "resize:300x200,explode"])
        .env_remove("DISPLAY")
        .output()
        .expect("running glyphcast view");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--script: 'explode'"), "{stderr}");
}

#[test]
fn three_slices_move_one_at_a_time() {
    let Some(x) = Xvfb::start("three_slices_move_one_at_a_time") else {
        return;
    };
    let volume = data("tests/data/dipy/func_coef.nii.gz");
    let (shot, seen) = (out("slices-shot.png"), out("slices-scene.json"));
    // From the middles: the coronal slice one on, the axial one back.
    let script = "active:2,slice:+1,active:3,slice:-1,wait";
    let args = [
        "--sh",
        &volume,
        "--basis",
        "tournier07",
        "--legacy",
        "--slices",
        "mid",
        "--width",
        "160",
        "--height",
        "120",
        "--frames",
        "8",
        "--script",
        script,
        "--screenshot",
        path_str(&shot),
        "--save-scene",
        path_str(&seen),
    ];
    let output = x.view(&args);
    assert_clean(&output);

    let sh = glyphcast_dmri::volume::VolumeKind::Sh {
        basis: glyphcast::scene::ShBasis::Tournier07,
        legacy: true,
    };
    let loaded = glyphcast_dmri::volume::load_volume(Path::new(&volume), sh).expect("the volume");
    let middle = loaded.dims.map(|n| n / 2);
    let planes = [middle[0], middle[1] + 1, middle[2] - 1];
    let map = &loaded.voxel_to_world;
    let (origin, inverse) = (map.voxel_center(glam::DVec3::ZERO), map.linear().inverse());
    let scene = glyphcast::scene::Scene::load(&seen).expect("the saved scene");
    assert_eq!(scene.glyph_sets.len(), 3, "one glyph set per slice");
    for (axis, set) in scene.glyph_sets.iter().enumerate() {
        assert!(!set.centers.is_empty(), "set {axis} is empty");
        for center in &set.centers {
            let voxel = inverse * (*center - origin);
            assert!(
                (voxel[axis] - planes[axis] as f64).abs() < 1e-6,
                "set {axis}: a glyph at voxel {voxel} is off the plane {}",
                planes[axis]
            );
        }
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("active slice: only"), "{stderr}");
}

#[test]
fn view_takes_the_figure_options_as_render_does() {
    let Some(x) = Xvfb::start("view_takes_the_figure_options_as_render_does") else {
        return;
    };
    // f = x^2 - 0.6 y^2 + 0.3 z^2: a negative pair of lobes along y.
    let scene = out("signed.json");
    std::fs::write(
        &scene,
        r#"{"version": 1,
  "glyphs": [{"kind": "tensor", "order": 2, "symmetric": true, "negative": "abs",
    "centers": [[0, 0, 0]], "scale": 1, "coeffs": [[1, 0, 0, -0.6, 0, 0.3]]}],
  "camera": {"projection": "perspective", "eye": [1.5, -3, 2], "target": [0, 0, 0],
    "up": [0, 0, 1], "fov_y_deg": 40},
  "image": {"width": 160, "height": 120}}"#,
    )
    .expect("writing the scene");
    let figure = [
        "--negative",
        "hide",
        "--color",
        "sign",
        "--background",
        "white",
    ];
    let shot = out("signed-shot.png");
    let mut args = vec![
        path_str(&scene),
        "--frames",
        "3",
        "--screenshot",
        path_str(&shot),
    ];
    args.extend(figure);
    assert_clean(&x.view(&args));
    let expected = render(&scene, "signed-render.png", &figure);
    assert_eq!(differing_pixels(&shot, &expected, 0).0, 0);
    let abs = [
        "--negative",
        "abs",
        "--color",
        "sign",
        "--background",
        "white",
    ];
    let shown = render(&scene, "signed-abs.png", &abs);
    assert!(
        differing_pixels(&shot, &shown, 40).0 > 100,
        "--negative hide changed nothing"
    );
}

#[test]
fn the_underlay_moves_with_the_slice() {
    let Some(x) = Xvfb::start("the_underlay_moves_with_the_slice") else {
        return;
    };
    let (tensors, fa) = common::underlay::tensors_with_underlay(&out("underlay-files"));
    let (shot, window) = (out("underlay-shot.png"), out("underlay-window.png"));
    let volume = [
        "--tensor",
        &tensors,
        "--order",
        "2",
        "--underlay",
        &fa,
        "--width",
        "120",
        "--height",
        "100",
    ];
    let mut args = volume.to_vec();
    args.extend([
        "--frames",
        "4",
        "--script",
        "slice:+1,wait",
        "--screenshot",
        path_str(&shot),
        "--capture-window",
        path_str(&window),
    ]);
    assert_clean(&x.view(&args));
    // The middle axial slice is k = 2; one on is k = 3, as render draws it.
    let render_slice = |slice: &str, name: &str| -> PathBuf {
        let png = out(name);
        let status = Command::new(BIN)
            .arg("render")
            .args(volume)
            .args(["--slice", slice, "--validation", "-o", path_str(&png)])
            .status()
            .expect("running glyphcast render");
        assert!(status.success(), "glyphcast render --slice {slice}");
        png
    };
    let moved = render_slice("axial:3", "underlay-k3.png");
    let before = render_slice("axial:2", "underlay-k2.png");
    assert_window_matches(&window, &shot);
    let (count, worst, _) = differing_pixels(&shot, &moved, 1);
    assert_eq!(
        count, 0,
        "the screenshot differs from render --slice axial:3 (largest {worst})"
    );
    assert!(
        differing_pixels(&shot, &before, 10).0 > 500,
        "the underlay did not move with the slice"
    );
}

/// Switching shadows on over an underlay darkens the underlay too, as `render --shadows`
/// draws it, pixel for pixel.
#[test]
fn shadows_fall_on_the_underlay_in_the_viewer() {
    let Some(x) = Xvfb::start("shadows_fall_on_the_underlay_in_the_viewer") else {
        return;
    };
    let (tensors, fa) = common::underlay::tensors_with_underlay(&out("underlay-shadow-files"));
    let shot = out("underlay-shadows-shot.png");
    let volume = [
        "--tensor",
        &tensors,
        "--order",
        "2",
        "--underlay",
        &fa,
        "--width",
        "120",
        "--height",
        "100",
        "--light",
        "-0.8,0.3,0.5",
    ];
    let mut args = volume.to_vec();
    args.extend([
        "--frames",
        "3",
        "--script",
        "shadows:toggle",
        "--screenshot",
        path_str(&shot),
    ]);
    assert_clean(&x.view(&args));
    let render_with = |extra: &[&str], name: &str| -> PathBuf {
        let png = out(name);
        let status = Command::new(BIN)
            .arg("render")
            .args(volume)
            .args(extra)
            .args(["--validation", "-o", path_str(&png)])
            .status()
            .expect("running glyphcast render");
        assert!(status.success(), "glyphcast render {extra:?}");
        png
    };
    let shadowed = render_with(&["--shadows"], "underlay-shadows-render.png");
    let plain = render_with(&[], "underlay-no-shadows-render.png");
    let (count, worst, _) = differing_pixels(&shot, &shadowed, 0);
    assert_eq!(
        count, 0,
        "the screenshot differs from render --shadows (largest {worst})"
    );
    assert!(
        differing_pixels(&shot, &plain, 0).0 > 100,
        "shadows changed too little"
    );
}

/// Orbiting half a turn (a drag of the window's height) shows the slice from behind: the
/// underlay's plane, placed behind the glyphs for the first camera, must move to the new
/// far side of the slice and not hide the glyphs. Every glyph pixel of the view without
/// the underlay is the same with it (it failed on 3,162 of 3,176 before the fix), and the
/// underlay fills the background.
#[test]
fn the_underlay_stays_behind_the_glyphs_from_the_other_side() {
    let Some(x) = Xvfb::start("the_underlay_stays_behind_the_glyphs_from_the_other_side") else {
        return;
    };
    let (tensors, fa) = common::underlay::tensors_with_underlay(&out("underlay-behind-files"));
    let view = |underlay: Option<&str>, name: &str| -> (PathBuf, PathBuf) {
        let (shot, window) = (
            out(&format!("{name}-shot.png")),
            out(&format!("{name}-window.png")),
        );
        let mut args = vec!["--tensor", &tensors, "--order", "2", "--width", "120"];
        args.extend([
            "--height",
            "100",
            "--frames",
            "4",
            "--script",
            "orbit:100:0,wait",
        ]);
        args.extend([
            "--screenshot",
            path_str(&shot),
            "--capture-window",
            path_str(&window),
        ]);
        if let Some(underlay) = underlay {
            args.extend(["--underlay", underlay]);
        }
        assert_clean(&x.view(&args));
        (shot, window)
    };
    let (glyphs, _) = view(None, "behind-glyphs");
    let (with_underlay, window) = view(Some(&fa), "behind-underlay");
    assert_window_matches(&window, &with_underlay);
    let (w, h, alone) = read_png_rgba8(&glyphs).expect("reading the glyphs' view");
    let (_, _, both) = read_png_rgba8(&with_underlay).expect("reading the underlay's view");
    assert_eq!(alone.len(), both.len());
    let background = &alone[..4];
    let (mut glyph_pixels, mut hidden, mut shown) = (0, 0, 0);
    for (a, b) in alone.chunks_exact(4).zip(both.chunks_exact(4)) {
        if a == background {
            shown += usize::from(a != b);
        } else {
            glyph_pixels += 1;
            hidden += usize::from(a.iter().zip(b).any(|(p, q)| p.abs_diff(*q) > 1));
        }
    }
    let pixels = (w * h) as usize;
    assert!(
        glyph_pixels > pixels / 10,
        "only {glyph_pixels} glyph pixels of {pixels}: the view shows too little to judge"
    );
    assert_eq!(
        hidden, 0,
        "the underlay covers {hidden} of {glyph_pixels} glyph pixels seen from behind the slice"
    );
    assert!(
        shown > (pixels - glyph_pixels) / 2,
        "the underlay shows on only {shown} background pixels"
    );
}

/// The frames-in-flight statistics a scripted run prints at its end: frames in flight,
/// glyph uploads replaced, retired uploads still held.
fn in_flight_stats(stderr: &str) -> (usize, u32, usize) {
    let line = stderr
        .lines()
        .find(|l| l.starts_with("frames in flight: "))
        .unwrap_or_else(|| panic!("no frames-in-flight line in {stderr}"));
    let numbers: Vec<usize> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().expect("a count"))
        .collect();
    // "frames in flight: N; glyph uploads replaced: R (F while ...), retired ...: H"
    assert_eq!(numbers.len(), 4, "{line}");
    (numbers[0], numbers[1] as u32, numbers[3])
}

/// The window with 2 frames in flight (every viewer test runs under synchronization
/// validation, `Xvfb::view`): glyphs replaced by a slice step and a method switch are
/// retired, not waited for, and freed once both slots have begun again; what it shows is
/// the headless render of the scene as shown, in a single view and in a montage with the
/// colour bar.
#[test]
fn two_frames_in_flight_stay_clean_under_synchronization_validation() {
    let Some(x) = Xvfb::start("two_frames_in_flight_stay_clean_under_synchronization_validation")
    else {
        return;
    };
    let volume = data("tests/data/dipy/func_coef.nii.gz");
    let sh = ["--sh", volume.as_str(), "--basis", "tournier07", "--legacy"];
    let (shot, window, seen) = (
        out("in-flight-shot.png"),
        out("in-flight-window.png"),
        out("in-flight-scene.json"),
    );
    // A slice step and a method switch each replace the glyphs while the previous frame
    // (the other slot's) may still be in flight; the camera moves between them, so every
    // frame writes its own slot's frame block.
    let mut args = sh.to_vec();
    args.extend([
        "--width",
        "160",
        "--height",
        "120",
        "--frames-in-flight",
        "2",
        "--frames",
        "8",
        "--script",
        "orbit:20:10,slice:+1,zoom:0.9,method:fixed,pan:3:-2",
        "--screenshot",
        path_str(&shot),
        "--capture-window",
        path_str(&window),
        "--save-scene",
        path_str(&seen),
    ]);
    let output = x.view(&args);
    assert_clean(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    let (in_flight, replaced, held) = in_flight_stats(&stderr);
    assert_eq!(in_flight, 2);
    // The slice step and the method switch went through the renderer's retirement; by
    // the end every slot has begun frames since, so no retired upload is left.
    assert_eq!(replaced, 2, "{stderr}");
    assert_eq!(held, 0, "{stderr}");
    // The scene as shown, rendered headless, is the screenshot, and the window drawn
    // with 2 frames in flight showed it.
    let expected = render(&seen, "in-flight-render.png", &["--method", "fixed"]);
    assert_eq!(differing_pixels(&shot, &expected, 0).0, 0);
    assert_window_matches(&window, &expected);

    // One frame in flight draws the same: the slot count changes when frames wait, not
    // what they show.
    let one = out("in-flight-one-window.png");
    let mut single = args.clone();
    let at = single
        .iter()
        .position(|a| *a == "--frames-in-flight")
        .expect("the option")
        + 1;
    single[at] = "1";
    let at = single
        .iter()
        .position(|a| *a == "--capture-window")
        .expect("the option")
        + 1;
    single[at] = path_str(&one);
    let output = x.view(&single);
    assert_clean(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(in_flight_stats(&stderr), (1, 2, 0), "{stderr}");
    assert_eq!(differing_pixels(&one, &window, 0).0, 0);

    // A montage with the colour bar: every slot's offscreen target and strip buffer,
    // through a slice step, under synchronization validation too.
    let (shot, window) = (
        out("in-flight-views-shot.png"),
        out("in-flight-views-window.png"),
    );
    let mut args = sh.to_vec();
    args.extend([
        "--views",
        "axial,coronal",
        "--width",
        "96",
        "--height",
        "96",
        "--color",
        "magnitude",
        "--colorbar",
        "--frames",
        "5",
        "--script",
        "wait,slice:+1,orbit:10:0",
        "--screenshot",
        path_str(&shot),
        "--capture-window",
        path_str(&window),
    ]);
    let output = x.view(&args);
    assert_clean(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(in_flight_stats(&stderr), (2, 1, 0), "{stderr}");
    assert_window_matches(&window, &shot);
}

#[test]
fn frames_in_flight_out_of_range_is_a_usage_error() {
    for n in ["0", "5"] {
        let output = Command::new(BIN)
            .args(["view", &data("tests/scenes/sphere.json"), "--frames", "1"])
            .args(["--frames-in-flight", n])
            .env_remove("DISPLAY")
            .output()
            .expect("running glyphcast view");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{n}: {stderr}");
        assert!(stderr.contains("--frames-in-flight"), "{n}: {stderr}");
    }
}
