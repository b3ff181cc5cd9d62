//! Hardening (issue 11): bad data, bad options, extreme settings, large images and
//! interrupts, each through the real binary. Every case gets one clear `error:` line
//! (exit 1 for bad data, 2 for a bad command line), writes nothing and loses nothing of
//! the user's; an interrupt removes the temporaries and leaves a set of outputs all old
//! or all new.
use crate::common;
use common::{dipy_data, fresh_dir, glyphcast};
use ndarray::Array4;
use std::path::{Path, PathBuf};
use std::process::Output;

fn path_str(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

fn scene(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/scenes")
        .join(name)
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("listing")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Expects exit `code` and exactly one `error:` line, no panic, nothing new in
/// `dir` but the files in `keep`; returns the error line.
fn expect_error(out: &Output, code: i32, dir: &Path, keep: &[&str]) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(code),
        "exit code; stderr:\n{stderr}"
    );
    assert!(!stderr.contains("panicked"), "panic:\n{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "one error line expected:\n{stderr}");
    assert_eq!(names_in(dir), keep, "files left behind");
    errors[0].to_owned()
}

// ---- fit: data that cannot be fitted, and degenerate directions.

/// The weighted directions of small_64D (its bvec: one row per volume, b=0 rows NaN).
fn small_64d_directions() -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(dipy_data("small_64D.bvec")).expect("bvec");
    text.lines()
        .map(|line| {
            let v: Vec<f64> = line
                .split_whitespace()
                .map(|t| t.parse().expect("number"))
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// A 2x2x2 DWI on small_64D's table: S0 = 1000 and an anisotropic tensor
/// (D = 0.0005 + 0.001 gx^2 mm^2/s); `edit` changes the signal before it is written.
fn write_dwi(path: &Path, edit: impl Fn(&mut Array4<f32>)) {
    let bvals: Vec<f64> = std::fs::read_to_string(dipy_data("small_64D.bval"))
        .expect("bval")
        .split_whitespace()
        .map(|t| t.parse().expect("number"))
        .collect();
    let directions = small_64d_directions();
    let signal = |v: usize| {
        if bvals[v] < 50.0 {
            return 1000.0;
        }
        let gx = directions[v][0];
        (1000.0 * (-bvals[v] * (0.0005 + 0.001 * gx * gx)).exp()) as f32
    };
    let mut dwi = Array4::from_shape_fn((2, 2, 2, bvals.len()), |(_, _, _, v)| signal(v));
    edit(&mut dwi);
    nifti::writer::WriterOptions::new(path)
        .write_nifti(&dwi)
        .expect("writing the test DWI");
}

/// `fit` on small_64D's b-values (order 2 unless `options` give one).
fn fit(dwi: &Path, bvec: &Path, output: &Path, options: &[&str]) -> Output {
    let bval = dipy_data("small_64D.bval");
    let mut args = vec![
        "fit",
        path_str(dwi),
        "--bval",
        path_str(&bval),
        "--bvec",
        path_str(bvec),
        "-o",
        path_str(output),
    ];
    args.extend(options);
    if !options.contains(&"--order") {
        args.extend(["--order", "2"]);
    }
    glyphcast(&args)
}

/// All-NaN, all-zero and negative series are errors naming the DWI (no all-zero
/// output); a series with one NaN voxel is fitted, with a warning that counts it.
#[test]
fn fit_refuses_data_with_nothing_to_fit_and_counts_what_it_drops() {
    let inputs = fresh_dir("hardening-fit-data");
    let bvec = dipy_data("small_64D.bvec");
    let cases: [(&str, f32, &str); 3] = [
        ("nan", f32::NAN, "NaN"),
        ("zero", 0.0, "zero"),
        ("negative", -5.0, "negative"),
    ];
    for (name, value, word) in cases {
        let dwi = inputs.join(format!("{name}.nii"));
        write_dwi(&dwi, |s| s.fill(value));
        let out_dir = fresh_dir(&format!("hardening-fit-{name}-out"));
        let run = fit(&dwi, &bvec, &out_dir.join("out.nii.gz"), &[]);
        let line = expect_error(&run, 1, &out_dir, &[]);
        assert!(
            line.contains(path_str(&dwi)),
            "{name}: file not named: {line}"
        );
        assert!(line.contains(word), "{name}: '{word}' not said: {line}");
        let run = fit(&dwi, &bvec, &out_dir.join("out.nii.gz"), &["--sh"]);
        expect_error(&run, 1, &out_dir, &[]);
    }

    let dwi = inputs.join("one_nan.nii");
    write_dwi(&dwi, |s| s[[0, 0, 0, 7]] = f32::NAN);
    let out_dir = fresh_dir("hardening-fit-one-nan-out");
    let run = fit(&dwi, &bvec, &out_dir.join("out.nii.gz"), &["--quiet"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning:") && stderr.contains("1 voxel(s) with NaN"),
        "no warning counting the NaN voxel:\n{stderr}"
    );
    assert_eq!(names_in(&out_dir), ["out.nii.gz"]);
}

/// 64 identical directions: the SH fit refuses them (its regularisation alone would make
/// them solvable) as the tensor fit does, naming the bvec file.
#[test]
fn identical_directions_are_refused_by_both_fits() {
    let inputs = fresh_dir("hardening-fit-directions");
    let dwi = inputs.join("dwi.nii");
    write_dwi(&dwi, |_| {});
    let rows: Vec<&str> = (0..65)
        .map(|v| if v == 0 { "0 0 0" } else { "0.6 0.8 0" })
        .collect();
    let bvec = inputs.join("same.bvec");
    std::fs::write(&bvec, rows.join("\n")).expect("bvec");
    for options in [&["--sh", "--order", "4"][..], &["--order", "2"]] {
        let out_dir = fresh_dir("hardening-fit-directions-out");
        let run = fit(&dwi, &bvec, &out_dir.join("out.nii.gz"), options);
        let line = expect_error(&run, 1, &out_dir, &[]);
        assert!(line.contains("same.bvec"), "{options:?}: {line}");
        assert!(line.contains("directions"), "{options:?}: {line}");
    }
}

/// Bad options of fit are usage errors (exit 2) that name the option; an output in a
/// missing folder is refused before anything is read, in one plain line.
#[test]
fn fit_options_and_outputs_are_checked_first() {
    let inputs = fresh_dir("hardening-fit-options");
    let dwi = inputs.join("dwi.nii");
    write_dwi(&dwi, |_| {});
    let bvec = dipy_data("small_64D.bvec");
    let out_dir = fresh_dir("hardening-fit-options-out");
    let output = out_dir.join("out.nii.gz");
    for (options, named) in [
        (&["--sh", "--lambda", "1e300"][..], "--lambda"),
        (&["--sh", "--lambda=-1"], "--lambda"),
        (&["--order", "3"], "--order"),
        (&["--sh", "--basis", "fsl"], "--basis"),
    ] {
        let line = expect_error(&fit(&dwi, &bvec, &output, options), 2, &out_dir, &[]);
        assert!(line.contains(named), "{options:?}: {line}");
    }
    let line = expect_error(
        &fit(&dwi, &bvec, &out_dir.join("out.jpg"), &[]),
        2,
        &out_dir,
        &[],
    );
    assert!(line.contains("out.jpg"), "{line}");
    let missing = out_dir.join("missing").join("x.nii.gz");
    let line = expect_error(&fit(&dwi, &bvec, &missing, &[]), 1, &out_dir, &[]);
    assert!(line.contains("does not exist"), "{line}");
    assert!(!line.contains('{'), "a debug value: {line}");
}

// ---- render, view and stiffness: options, outputs and messages.

/// Outputs whose names say another format, settings outside the range float32 draws
/// reliably, a size past the limit and a missing --basis are usage errors (exit 2)
/// naming the option, refused before a device is opened.
#[test]
fn render_usage_errors_exit_2_before_any_work() {
    let dir = fresh_dir("hardening-render-usage");
    let sphere = scene("sphere.json");
    let out = |name: &str| dir.join(name).to_str().expect("path").to_owned();
    let coefficients = dipy_data("func_coef.nii.gz");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["-o".into(), out("out.jpg")], "-o/--output"),
        (
            vec![
                "-o".into(),
                out("a.png"),
                "--depth-out".into(),
                out("d.png"),
            ],
            "--depth-out",
        ),
        (
            vec!["--method=fixed".into(), "--step=1e-4".into()],
            "--step",
        ),
        (
            vec!["--method=interval".into(), "--precision=1e-6".into()],
            "--precision",
        ),
        (vec!["--width=16385".into()], "--width"),
        (
            vec!["--save-scene".into(), out("scene.png")],
            "--save-scene",
        ),
    ];
    let default_output = out("out.png");
    for (extra, named) in cases {
        let mut args = vec!["render", path_str(&sphere)];
        if !extra.iter().any(|a| a == "-o") {
            args.extend(["-o", default_output.as_str()]);
        }
        args.extend(extra.iter().map(String::as_str));
        let run = glyphcast(&args);
        let line = expect_error(&run, 2, &dir, &[]);
        assert!(line.contains(named), "{extra:?}: {line}");
        assert!(
            !String::from_utf8_lossy(&run.stderr).contains("device:"),
            "{extra:?}: a device was opened first"
        );
    }
    let run = glyphcast(&[
        "render",
        "--sh",
        path_str(&coefficients),
        "-o",
        &out("out.png"),
    ]);
    let line = expect_error(&run, 2, &dir, &[]);
    assert!(line.contains("--basis"), "{line}");
}

/// Scene keys are quoted with control characters escaped and long keys cut short: the
/// message stays one short line that cannot drive the terminal.
#[test]
fn scene_keys_in_messages_are_escaped_and_cut_short() {
    let dir = fresh_dir("hardening-scene-keys");
    let text = std::fs::read_to_string(scene("sphere.json")).expect("scene");
    let with_key = |key: &str| {
        let mut doc: serde_json::Value = serde_json::from_str(&text).expect("json");
        doc[key] = serde_json::json!(1);
        doc.to_string()
    };
    let long_key = "k".repeat(2 << 20);
    for (name, key) in [
        ("control.json", "bad\nline\u{1b}[2J"),
        ("long.json", long_key.as_str()),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, with_key(key)).expect("scene");
        let out_dir = fresh_dir("hardening-scene-keys-out");
        let run = glyphcast(&[
            "render",
            path_str(&path),
            "-o",
            path_str(&out_dir.join("out.png")),
        ]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        let line = expect_error(&run, 1, &out_dir, &[]);
        assert_eq!(stderr.lines().count(), 1, "{name}: one line:\n{stderr}");
        assert!(!stderr.contains('\u{1b}'), "{name}: raw escape: {stderr}");
        assert!(
            line.contains(name) && line.contains("unknown key"),
            "{line}"
        );
        assert!(line.len() < 600, "{name}: {} bytes", line.len());
    }
}

/// A bare JSON list of Voigt rows is read as JSON whatever the file's name, giving the
/// same scene as the CSV; a broken one is a JSON error, not a CSV one.
#[test]
fn stiffness_reads_a_bare_json_list() {
    let dir = fresh_dir("hardening-stiffness");
    let rows = [
        [170.0, 124.0, 124.0, 0.0, 0.0, 0.0],
        [124.0, 170.0, 124.0, 0.0, 0.0, 0.0],
        [124.0, 124.0, 170.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 75.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 75.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, 75.0],
    ];
    let csv: Vec<String> = rows
        .iter()
        .map(|r| r.map(|v| v.to_string()).join(","))
        .collect();
    std::fs::write(dir.join("c.csv"), csv.join("\n")).expect("csv");
    std::fs::write(dir.join("list.txt"), serde_json::json!(rows).to_string()).expect("json");
    let convert = |input: &str, output: &str| {
        glyphcast(&[
            "stiffness",
            path_str(&dir.join(input)),
            "-o",
            path_str(&dir.join(output)),
        ])
    };
    for (input, output) in [("c.csv", "from_csv.json"), ("list.txt", "from_list.json")] {
        let run = convert(input, output);
        assert!(run.status.success(), "{input}: {run:?}");
    }
    assert_eq!(
        std::fs::read(dir.join("from_csv.json")).expect("scene"),
        std::fs::read(dir.join("from_list.json")).expect("scene")
    );
    std::fs::write(dir.join("broken.txt"), "[[1, 2], oops").expect("broken");
    let run = convert("broken.txt", "broken.json");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("broken.txt") && stderr.contains("JSON"),
        "{stderr}"
    );
    assert!(!dir.join("broken.json").exists());
}

/// view refuses a method it cannot draw and a screenshot name of another format before
/// it opens a window (no DISPLAY is needed to be told).
#[test]
fn view_checks_method_and_outputs_before_the_window() {
    let dir = fresh_dir("hardening-view");
    let sphere = scene("sphere.json");
    let shot = dir.join("shot.jpg");
    for (extra, named) in [
        (vec!["--method", "mesh:2"], "--method"),
        (vec!["--screenshot", path_str(&shot)], "--screenshot"),
    ] {
        let mut args = vec!["view", path_str(&sphere), "--frames", "1"];
        args.extend(extra.iter().copied());
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_glyphcast"))
            .args(&args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("running glyphcast");
        let line = expect_error(&run, 2, &dir, &[]);
        assert!(line.contains(named), "{extra:?}: {line}");
    }
}

// ---- large images and interrupts.

/// A large image under a memory limit is an error (exit 1), not an abort: the
/// read-back and encoding buffers are allocated fallibly, GPU memory reports its own
/// failure. Which allocation fails first depends on the driver; each is one clear line.
#[test]
fn a_large_image_under_a_memory_limit_is_an_error() {
    let dir = fresh_dir("hardening-large");
    let command = format!(
        "ulimit -v 2500000 && exec '{}' render '{}' --width 8192 --height 8192 -o '{}' --depth-out '{}'",
        env!("CARGO_BIN_EXE_glyphcast"),
        path_str(&scene("sphere.json")),
        path_str(&dir.join("big.png")),
        path_str(&dir.join("big.npy")),
    );
    let run = std::process::Command::new("sh")
        .args(["-c", &command])
        .env("GLYPHCAST_VALIDATION", "1")
        .output()
        .expect("running glyphcast under a memory limit");
    let line = expect_error(&run, 1, &dir, &[]);
    assert!(line.to_lowercase().contains("memory"), "{line}");
}

/// Signals a render while it writes its outputs (once a temporary has appeared) and
/// checks the exit code, that no temporary is left and that the user's outputs are
/// both old or both new.
fn interrupt_during_write(signal: &str, code: i32) {
    let dir = fresh_dir(&format!("hardening-signal-{signal}"));
    let (png, npy) = (dir.join("out.png"), dir.join("out.npy"));
    std::fs::write(&png, b"old image").expect("old image");
    std::fs::write(&npy, b"old depth").expect("old depth");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_glyphcast"))
        .args([
            "render",
            path_str(&scene("sphere.json")),
            "--width",
            "4096",
            "--height",
            "4096",
            "-o",
            path_str(&png),
            "--depth-out",
            path_str(&npy),
        ])
        .env("GLYPHCAST_VALIDATION", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("starting glyphcast");
    let started = std::time::Instant::now();
    let temporary = || names_in(&dir).iter().any(|n| n.ends_with(".tmp"));
    while !temporary() {
        assert!(
            child.try_wait().expect("polling").is_none(),
            "the render ended before a temporary was seen"
        );
        assert!(started.elapsed().as_secs() < 300, "no temporary appeared");
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    let sent = std::process::Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(sent.success());
    let status = child.wait().expect("waiting");
    assert_eq!(status.code(), Some(code), "{signal}: {status:?}");
    assert_eq!(names_in(&dir), ["out.npy", "out.png"], "temporaries left");
    let old = (
        std::fs::read(&png).expect("png") == b"old image",
        std::fs::read(&npy).expect("npy") == b"old depth",
    );
    assert!(
        old.0 == old.1,
        "{signal}: half of the set replaced: {old:?}"
    );
    if !old.0 {
        glyphcast::io::png::read_png_rgba8(&png).expect("a complete new image");
    }
}

#[test]
fn sigint_during_a_write_removes_temporaries() {
    interrupt_during_write("INT", 130);
}

#[test]
fn sigterm_during_a_write_removes_temporaries() {
    interrupt_during_write("TERM", 143);
}
