//! Requests the command line refuses rather than draw something other than asked or
//! report a misleading cause: scene values beyond float32's range (exit 1), settings
//! that the chosen method or colour would ignore, bench sizes and frame counts no
//! measurement can take, and a NIfTI DWI fitted without its gradient files (exit 2).
//! Each gets one `error:` line naming the file and field or the settings, and nothing is
//! written.
use crate::common;
use common::{fresh_dir, glyphcast, text, write_nifti};
use std::path::Path;

/// Runs `args`; expects exit `code`, no panic, one `error:` line holding every word of
/// `words`, and nothing new in `dir`. Returns the line.
fn refused(args: &[&str], code: i32, dir: &Path, words: &[&str]) -> String {
    let before = std::fs::read_dir(dir).expect("listing").count();
    let run = glyphcast(args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(code), "{args:?}:\n{stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: panic:\n{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{args:?}: one error line:\n{stderr}");
    for word in words {
        assert!(
            errors[0].contains(word),
            "{args:?}: '{word}' not in: {}",
            errors[0]
        );
    }
    let after = std::fs::read_dir(dir).expect("listing").count();
    assert_eq!(after, before, "{args:?} wrote into {}", dir.display());
    errors[0].to_owned()
}

/// Two order-2 tensors; `coeff` is the first one's xx entry, `eye` the camera's x.
fn dti_scene(dir: &Path, name: &str, coeff: &str, eye: &str) -> String {
    let path = dir.join(name);
    let json = format!(
        r#"{{"version": 1, "glyphs": [{{"kind": "tensor", "order": 2,
            "centers": [[0, 0, 0], [1, 0, 0]], "scale": 0.4,
            "coeffs": [[{coeff}, 0, 0, 1, 0, 1], [1, 0.1, 0, 1, 0, 1]]}}],
            "camera": {{"eye": [{eye}, -5, 2], "target": [0.5, 0, 0]}},
            "image": {{"width": 16, "height": 16}}}}"#
    );
    std::fs::write(&path, json).expect("writing a scene");
    path.display().to_string()
}

/// Finite in float64 but infinite in the GPU's float32: the glyph or the view would
/// vanish with exit 0. Refused as bad data, naming the file, the field and the glyph.
#[test]
fn scene_values_beyond_float32_are_refused() {
    let dir = fresh_dir("refusals-float32");
    let inputs = fresh_dir("refusals-float32-in");
    let png = dir.join("out.png");
    let coeff = dti_scene(&inputs, "coeff.json", "1e39", "0");
    refused(
        &["render", &coeff, "-o", text(&png)],
        1,
        &dir,
        &[
            "coeff.json",
            "glyphs[0].coeffs[0][0]",
            "1e39 is beyond float32's range",
        ],
    );
    let eye = dti_scene(&inputs, "eye.json", "1", "1e39");
    refused(
        &["render", &eye, "-o", text(&png)],
        1,
        &dir,
        &[
            "eye.json",
            "camera.eye[0]",
            "1e39 is beyond float32's range",
        ],
    );
    // float32's own range is drawn.
    let fine = dti_scene(&inputs, "fine.json", "1e38", "0");
    let run = glyphcast(&["render", &fine, "-o", text(&png)]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

/// Settings that the colour or method asked for would not read are refused, naming the
/// settings, before anything is drawn.
#[test]
fn settings_that_would_be_ignored_are_refused() {
    let dir = fresh_dir("refusals-ignored");
    let inputs = fresh_dir("refusals-ignored-in");
    let scene = dti_scene(&inputs, "dti.json", "1", "0");
    let png = dir.join("out.png");
    let render = |extra: &[&str], words: &[&str]| {
        let mut args = vec!["render", scene.as_str(), "-o", text(&png)];
        args.extend_from_slice(extra);
        refused(&args, 2, &dir, words)
    };
    render(
        &["--magnitude-range", "0:1"],
        &["--magnitude-range needs --color magnitude"],
    );
    render(
        &["--color", "sign", "--magnitude-range", "0:1"],
        &["--magnitude-range needs --color magnitude"],
    );
    render(
        &["--method", "exact", "--step", "0.01"],
        &[
            "--step 0.01",
            "--method fixed",
            "--method exact does not read it",
        ],
    );
    render(
        &["--precision", "0.5"],
        &[
            "--precision 0.5",
            "--method interval",
            "--method exact does not read it",
        ],
    );
    render(
        &["--method", "impostor", "--refine", "none"],
        &["--refine 'none'", "--method impostor does not read it"],
    );
    render(
        &["--glyph", "ellipsoid", "--negative", "hide"],
        &["--negative hide", "no negative lobes", "--glyph ellipsoid"],
    );
    // The same settings with a method and colour that read them are drawn.
    for extra in [
        &["--color", "magnitude", "--magnitude-range", "0:1"][..],
        &["--method", "fixed", "--step", "0.05", "--refine", "none"],
        &[
            "--method",
            "affine",
            "--precision",
            "0.5",
            "--refine",
            "none",
        ],
        &["--glyph", "ellipsoid", "--negative", "abs"],
    ] {
        let mut args = vec!["render", scene.as_str(), "-o", text(&png)];
        args.extend_from_slice(extra);
        let run = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{extra:?}: {stderr}");
    }
}

/// `bench --width 0` is refused as `render` refuses it (not as a GPU allocation
/// failure), and `--frames 0` is refused rather than measured as one frame.
#[test]
fn bench_refuses_sizes_and_frame_counts_it_cannot_measure() {
    let dir = fresh_dir("refusals-bench");
    let csv = dir.join("results.csv");
    assert!(!csv.exists());
    for (extra, words) in [
        (&["--width", "0"][..], &["--width 0", "must be in 1 to"][..]),
        (
            &["--height", "20000"],
            &["--height 20000", "must be in 1 to"],
        ),
        (&["--frames", "0"], &["--frames", "at least 1"]),
    ] {
        let mut args = vec!["bench", "--workload", "fodf:1:8", "--out", text(&dir)];
        args.extend_from_slice(extra);
        let line = refused(&args, 2, &dir, words);
        assert!(!line.contains("GPU memory"), "{line}");
    }
}

/// A NIfTI DWI carries no gradient table: without --bval and --bvec the fit is a usage
/// error naming them, not a complaint about MRtrix's dw_scheme.
#[test]
fn a_nifti_dwi_without_gradient_files_is_a_usage_error() {
    let dir = fresh_dir("refusals-fit");
    let inputs = fresh_dir("refusals-fit-in");
    let dwi = inputs.join("dwi.nii");
    let data = ndarray::ArrayD::from_elem(vec![2, 2, 2, 7], 100.0);
    write_nifti(&dwi, &data, glam::DMat4::IDENTITY);
    let out = dir.join("fit.nii.gz");
    let line = refused(
        &["fit", text(&dwi), "--order", "2", "-o", text(&out)],
        2,
        &dir,
        &["dwi.nii", "NIfTI", "--bval", "--bvec"],
    );
    assert!(!line.contains("no gradient table in the file"), "{line}");
}

/// A volume whose coefficients exceed float32's range once its scale factor is applied
/// (a float64 image can hold them too) is refused, naming the file and the voxel: a
/// scene saved from it could not be read back.
#[test]
fn volume_coefficients_beyond_float32_are_refused() {
    let dir = fresh_dir("refusals-volume");
    let inputs = fresh_dir("refusals-volume-in");
    let mut data = ndarray::ArrayD::from_elem(vec![2, 2, 1, 6], 0.0);
    for ((i, j), first) in [((0, 0), 1.0), ((1, 0), 1.0), ((0, 1), 1.0), ((1, 1), 10.0)] {
        data[[i, j, 0, 0]] = first;
        data[[i, j, 0, 3]] = 0.1 * first;
    }
    let path = inputs.join("sh.nii");
    write_nifti(&path, &data, glam::DMat4::IDENTITY);
    let mut bytes = std::fs::read(&path).expect("read");
    // scl_slope: 1e38 keeps 1 within float32 and takes 10 beyond it.
    common::nifti::set_f32(&mut bytes, 112, 1e38);
    std::fs::write(&path, bytes).expect("write");
    let png = dir.join("out.png");
    let args = [
        "render",
        "--sh",
        text(&path),
        "--basis",
        "tournier07",
        "-o",
        text(&png),
    ];
    refused(
        &args,
        1,
        &dir,
        &[
            "sh.nii",
            "voxel [1, 1, 0], coefficient 0",
            "beyond float32's range",
        ],
    );
}

/// `--path compute` is a setting the command line refuses, whatever stands in its way:
/// a method other than `exact`, glyphs other than the polynomial glyph (refused before
/// the device starts), an image over the device's buffer limit. Each is exit 2 and says
/// what to do instead.
#[test]
fn compute_path_refusals_are_usage_errors_with_a_way_out() {
    let dir = fresh_dir("refusals-compute");
    let inputs = fresh_dir("refusals-compute-in");
    let scene = dti_scene(&inputs, "dti.json", "1", "0");
    let png = dir.join("out.png");
    let render = |extra: &[&str]| -> Vec<String> {
        let mut args = vec!["render".to_owned(), scene.clone()];
        args.extend(extra.iter().map(|s| s.to_string()));
        args.extend(["-o".to_owned(), text(&png).to_owned()]);
        args
    };
    let run = |extra: &[&str], words: &[&str]| {
        let args = render(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&args, 2, &dir, words)
    };
    run(
        &["--path", "compute", "--method", "fixed"],
        &["--path compute", "--method exact", "fixed"],
    );
    let line = run(
        &["--path", "compute", "--glyph", "ellipsoid"],
        &["--path compute", "ellipsoid", "--path fragment"],
    );
    // Refused before any device: no device line on stderr.
    let args = render(&["--path", "compute", "--glyph", "ellipsoid"]);
    let stderr = String::from_utf8_lossy(
        &glyphcast(&args.iter().map(String::as_str).collect::<Vec<_>>()).stderr,
    )
    .into_owned();
    assert!(!stderr.contains("device:"), "{line}\n{stderr}");
    // 16384 x 16384 pixels of 4 bytes: 1 GiB, over any lavapipe's storage buffer range.
    run(
        &["--path", "compute", "--width", "16384", "--height", "16384"],
        &[
            "--path compute",
            "image buffer of 1073741824 bytes",
            "--samples",
            "--width/--height",
            "--path fragment",
        ],
    );
}

/// `--cull` ways a frame cannot take are refused naming the option and the reason
/// (exit 2): early outs with a method other than `exact`, passes with the impostor or a
/// mesh, either with the compute path. The default and `off` always apply.
#[test]
fn cull_ways_a_frame_cannot_take_are_refused() {
    let dir = fresh_dir("refusals-cull");
    let inputs = fresh_dir("refusals-cull-in");
    let scene = dti_scene(&inputs, "dti.json", "1", "0");
    let png = dir.join("out.png");
    for (extra, words) in [
        (
            ["--method", "fixed", "--cull", "early-out"],
            ["--cull early-out", "--method exact", "--method fixed"],
        ),
        (
            ["--method", "impostor", "--cull", "early-out"],
            ["--cull early-out", "--method exact", "--method impostor"],
        ),
        (
            ["--method", "impostor", "--cull", "passes"],
            ["--cull passes", "--method impostor", "every glyph"],
        ),
        (
            ["--path", "compute", "--cull", "passes"],
            ["--cull passes", "--path compute", "--path fragment"],
        ),
    ] {
        let mut args = vec!["render", scene.as_str(), "-o", text(&png)];
        args.extend(extra);
        refused(&args, 2, &dir, &words);
    }
    // `bench` reads them as `render` does, before any file or device.
    refused(
        &[
            "bench",
            text(&dir.join("missing.json")),
            "--method",
            "fixed",
            "--cull",
            "early-out",
        ],
        2,
        &dir,
        &["--cull early-out", "--method exact", "--method fixed"],
    );
}

/// A misspelled option value is refused before any file is read: the error names the
/// option, not the (missing) scene file or volume.
#[test]
fn option_values_are_checked_before_any_file_is_read() {
    let dir = fresh_dir("refusals-early");
    let missing = dir.join("missing.nii");
    let png = dir.join("out.png");
    for (flag, value) in [("--cull", "ocluded"), ("--path", "compuet")] {
        let line = refused(
            &[
                "render",
                "--sh",
                text(&missing),
                flag,
                value,
                "-o",
                text(&png),
            ],
            2,
            &dir,
            &[flag, value],
        );
        assert!(!line.contains("missing.nii"), "{line}");
        let line = refused(
            &[
                "render",
                text(&dir.join("missing.json")),
                flag,
                value,
                "-o",
                text(&png),
            ],
            2,
            &dir,
            &[flag, value],
        );
        assert!(!line.contains("missing.json"), "{line}");
    }
}

/// `--voxels` takes a value that begins with `-` (no tip to write `--`, which would not
/// work for an option's value): a negative index is the volume request's refusal.
#[test]
fn voxels_take_a_value_that_begins_with_a_minus() {
    let dir = fresh_dir("refusals-voxels");
    let inputs = fresh_dir("refusals-voxels-in");
    let path = inputs.join("sh.nii");
    let data = ndarray::ArrayD::from_elem(vec![2, 2, 2, 1], 1.0);
    write_nifti(&path, &data, glam::DMat4::IDENTITY);
    let png = dir.join("out.png");
    let args = [
        "render",
        "--sh",
        text(&path),
        "--basis",
        "tournier07",
        "--block",
        "--voxels",
        "-1:5,:,:",
        "-o",
        text(&png),
    ];
    let run = glyphcast(&args);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!stderr.contains("-- -1"), "{stderr}");
    refused(&args, 2, &dir, &["--voxels", "-1"]);
}

/// `--block` (or any volume option) without a volume says that it needs one, rather
/// than asking for a scene file.
#[test]
fn a_volume_option_without_a_volume_names_what_it_needs() {
    let dir = fresh_dir("refusals-block");
    let png = dir.join("out.png");
    let line = refused(
        &["render", "--block", "-o", text(&png)],
        2,
        &dir,
        &["--block", "--sh FILE"],
    );
    assert!(!line.contains("<SCENE>"), "{line}");
    refused(
        &["render", "-o", text(&png)],
        2,
        &dir,
        &["scene file", "--sh FILE"],
    );
}

/// `qc` of a DTI volume (recorded as a tensor by `glyphcast fit`) is refused with a way
/// out that exists: qc has no `--order`, so the message points at render and view.
#[test]
fn qc_of_a_tensor_volume_points_at_what_draws_it() {
    let dir = fresh_dir("refusals-qc");
    let inputs = fresh_dir("refusals-qc-in");
    let dti = common::dwi::fit_dti_small_64d(&inputs);
    let out = dir.join("qc");
    let line = refused(
        &["qc", text(&dti), "-o", text(&out)],
        1,
        &dir,
        &[
            "dti.nii.gz",
            "symmetric tensor of order 2",
            "render or view draw it as a tensor volume (with --order 2)",
            "qc and peaks read SH coefficients only",
        ],
    );
    assert!(!line.contains("read it as"), "{line}");
}
