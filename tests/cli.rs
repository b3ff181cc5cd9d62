//! The command line as a user meets it: bad input gives one clear line naming the file
//! and the field, a non-zero exit and no output files; good input writes a PNG and a
//! depth map in the scene format's .npy layout.
mod common;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn glyphcast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args(args)
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast")
}

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes")
}

fn fresh_dir(name: &str) -> PathBuf {
    let dir = common::output_dir().join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creating a test folder");
    dir
}

/// Runs `render` on `scene`, expects failure, and returns the error line.
fn expect_failure(scene: &Path, extra: &[&str], dir: &Path) -> String {
    let png = dir.join("out.png");
    let npy = dir.join("out.npy");
    let mut args = vec![
        "render",
        scene.to_str().expect("utf-8 path"),
        "-o",
        png.to_str().expect("path"),
    ];
    args.extend([
        "--depth-out",
        npy.to_str().expect("path"),
        "--width",
        "32",
        "--height",
        "32",
    ]);
    args.extend(extra);
    let out = glyphcast(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !out.status.success(),
        "{}: expected failure, got success",
        scene.display()
    );
    assert_ne!(out.status.code(), Some(0), "{}: exit code", scene.display());
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(
        errors.len(),
        1,
        "{}: one error line expected, got:\n{stderr}",
        scene.display()
    );
    assert!(
        !stderr.contains("panicked"),
        "{}: panic:\n{stderr}",
        scene.display()
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir).expect("listing").collect();
    assert!(
        leftovers.is_empty(),
        "{}: output left behind: {leftovers:?}",
        scene.display()
    );
    errors[0].to_owned()
}

#[test]
fn every_bad_scene_fails_cleanly_naming_file_and_field() {
    let dir = fresh_dir("bad-scenes");
    // File -> a word the message must contain (the field, or the kind of problem).
    let expected = [
        ("wrong_coeff_count.json", "coeffs"),
        ("order_out_of_range.json", "order"),
        ("nan.json", "NaN"),
        ("huge_number.json", "range"),
        ("unknown_value.json", "kind"),
        ("unknown_key.json", "centres"),
        ("malformed.json", "line"),
        ("missing_field.json", "version"),
        ("count_mismatch.json", "coeffs"),
        ("nonpositive_scale.json", "scale"),
        ("camera_up_parallel.json", "up"),
        ("wrong_type.json", "centers"),
    ];
    let mut seen = 0;
    let mut entries: Vec<_> = std::fs::read_dir(scenes().join("bad"))
        .expect("bad scenes")
        .flatten()
        .collect();
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        let line = expect_failure(&path, &[], &dir);
        assert!(
            line.contains(&name),
            "{name}: the error must name the file: {line}"
        );
        if let Some((_, word)) = expected.iter().find(|(f, _)| *f == name) {
            assert!(
                line.to_lowercase().contains(&word.to_lowercase()),
                "{name}: expected '{word}' in: {line}"
            );
        }
        seen += 1;
    }
    assert!(seen >= expected.len(), "only {seen} bad scenes found");
}

#[test]
fn missing_file_and_bad_options_fail_cleanly() {
    let dir = fresh_dir("bad-options");
    let missing = scenes().join("no-such-scene.json");
    let line = expect_failure(&missing, &[], &dir);
    assert!(line.contains("no-such-scene.json"), "{line}");
    let sphere = scenes().join("sphere.json");
    for (option, value) in [
        ("--refine", "bisect:x"),
        ("--step", "-1"),
        ("--color", "rainbow"),
        ("--method", "magic"),
    ] {
        let line = expect_failure(&sphere, &[&format!("{option}={value}")], &dir);
        assert!(line.contains(option), "{option} {value}: {line}");
    }
    // An unknown method is answered with every method there is.
    let line = expect_failure(&sphere, &["--method=magic"], &dir);
    assert!(line.contains("fixed, exact"), "{line}");
    // Offset glyphs are not polynomial surfaces: exact refuses them, naming both options.
    let line = expect_failure(&sphere, &["--method=exact", "--offset=0.1"], &dir);
    assert!(
        line.contains("--offset") && line.contains("exact"),
        "{line}"
    );
}

#[test]
fn exact_method_renders() {
    let dir = fresh_dir("render-exact");
    let png = dir.join("sphere.png");
    let npy = dir.join("sphere.npy");
    let scene = scenes().join("sphere.json");
    let out = glyphcast(&[
        "render",
        scene.to_str().expect("path"),
        "-o",
        png.to_str().expect("path"),
        "--depth-out",
        npy.to_str().expect("path"),
        "--width",
        "64",
        "--height",
        "48",
        "--method",
        "exact",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    let (_, depth) = glyphcast::io::npy::read_npy_f32(&npy).expect("reading the depth map");
    let hits = depth.iter().filter(|d| !d.is_nan()).count();
    assert!(hits > 50 && hits < depth.len(), "{hits} hits");
}

#[test]
fn render_writes_png_and_depth_map() {
    let dir = fresh_dir("render-ok");
    let png = dir.join("sphere.png");
    let npy = dir.join("sphere.npy");
    let scene = scenes().join("sphere.json");
    let out = glyphcast(&[
        "render",
        scene.to_str().expect("path"),
        "-o",
        png.to_str().expect("path"),
        "--depth-out",
        npy.to_str().expect("path"),
        "--width",
        "64",
        "--height",
        "48",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "render failed:\n{stderr}");
    assert!(
        stderr.contains("device:"),
        "the chosen device is printed:\n{stderr}"
    );
    let (w, h, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("reading the PNG");
    assert_eq!((w, h, rgba.len()), (64, 48, 64 * 48 * 4));
    let (shape, depth) = glyphcast::io::npy::read_npy_f32(&npy).expect("reading the depth map");
    assert_eq!(shape, vec![48, 64], "shape is (height, width)");
    let hits = depth.iter().filter(|d| !d.is_nan()).count();
    assert!(
        hits > 50 && hits < depth.len(),
        "the sphere covers part of the image: {hits}"
    );
    assert!(depth.iter().all(|d| d.is_nan() || *d > 0.0));
}

#[test]
fn demo_renders() {
    let dir = fresh_dir("demo");
    let png = dir.join("demo.png");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--width",
        "160",
        "--height",
        "120",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, _, rgba) = glyphcast::io::png::read_png_rgba8(&png).expect("demo PNG");
    // Glyphs are drawn: a good share of pixels differ from the background.
    let background = &rgba[0..4];
    let drawn = rgba.chunks_exact(4).filter(|p| *p != background).count();
    assert!(
        drawn > 160 * 120 / 10,
        "only {drawn} pixels differ from the background"
    );
}

#[test]
fn device_is_chosen_by_name_and_an_unknown_name_is_an_error() {
    let dir = fresh_dir("device");
    let png = dir.join("d.png");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--width",
        "32",
        "--height",
        "24",
        "--device",
        "0",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "device 0 must work:\n{stderr}");
    let name = stderr
        .lines()
        .find_map(|l| l.strip_prefix("device: "))
        .and_then(|l| l.split(" (").next())
        .expect("device line")
        .to_owned();
    std::fs::remove_file(&png).expect("removing");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--width",
        "32",
        "--height",
        "24",
        "--device",
        &name,
    ]);
    assert!(out.status.success(), "device by name '{name}' must work");
    std::fs::remove_file(&png).expect("removing");
    let out = glyphcast(&[
        "demo",
        "-o",
        png.to_str().expect("path"),
        "--device",
        "no-such-gpu",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("no-such-gpu") && stderr.contains(&name),
        "the error lists the devices:\n{stderr}"
    );
    assert!(!png.exists(), "no output on error");
}
