//! Scene files whose longest lists are `.npy` arrays beside them (docs/scene-format.md,
//! "Arrays beside the scene"): written by `bench --save-scene --scene-arrays`, drawn
//! exactly as the same scene with JSON lists, read in every layout NumPy writes, and
//! refused with the file, the field and the array named when an array is wrong.
use crate::common;
use common::{fresh_dir, glyphcast, text};
use std::path::Path;

/// A `.npy` file (version 1.0) of `descr` values (`<f4` or `<f8`) with `shape`, the
/// values given in the file's order; `fortran` sets the header's flag.
fn npy(path: &Path, descr: &str, fortran: bool, shape: &[usize], values: &[f64]) {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    let dims = if dims.len() == 1 {
        format!("{},", dims[0])
    } else {
        dims.join(", ")
    };
    let order = if fortran { "True" } else { "False" };
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': ({dims}), }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for &v in values {
        match descr {
            "<f4" => bytes.extend_from_slice(&(v as f32).to_le_bytes()),
            "<f8" => bytes.extend_from_slice(&v.to_le_bytes()),
            "<i4" => bytes.extend_from_slice(&(v as i32).to_le_bytes()),
            other => panic!("no writer for {other}"),
        }
    }
    std::fs::write(path, bytes).expect("writing a test .npy");
}

fn render(scene: &Path, png: &Path, npy: &Path) -> std::process::Output {
    glyphcast(&[
        "render",
        text(scene),
        "-o",
        text(png),
        "--depth-out",
        text(npy),
    ])
}

#[test]
fn array_scenes_draw_as_their_json_lists_do() {
    let dir = fresh_dir("scene-arrays");
    let (lists, arrays) = (dir.join("lists.json"), dir.join("arrays.json"));
    for (path, extra) in [(&lists, None), (&arrays, Some("--scene-arrays"))] {
        let mut args = vec![
            "bench",
            "--workload",
            "fodf:40:8",
            "--width",
            "96",
            "--height",
            "64",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--save-scene",
            text(path),
        ];
        args.extend(extra);
        let out = glyphcast(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let json = std::fs::read_to_string(&arrays).expect("scene");
    assert!(
        json.contains("\"coeffs\": \"arrays.0.coeffs.npy\""),
        "{json}"
    );
    assert!(
        json.contains("\"centers\": \"arrays.0.centers.npy\""),
        "{json}"
    );
    assert!(
        std::fs::metadata(&arrays).expect("scene").len() < 2000,
        "no numbers in the JSON"
    );
    let (png_a, npy_a) = (dir.join("a.png"), dir.join("a.npy"));
    let (png_l, npy_l) = (dir.join("l.png"), dir.join("l.npy"));
    for (scene, png, depth) in [(&arrays, &png_a, &npy_a), (&lists, &png_l, &npy_l)] {
        let out = render(scene, png, depth);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(
        std::fs::read(&png_a).unwrap(),
        std::fs::read(&png_l).unwrap()
    );
    assert_eq!(
        std::fs::read(&npy_a).unwrap(),
        std::fs::read(&npy_l).unwrap()
    );

    // The arrays as NumPy may also write them: float32, Fortran order, per-glyph scales
    // from a file. Coefficients that are exact in float32 draw the same picture.
    let scene = glyphcast::scene::Scene::load(&arrays).expect("loading the array scene");
    let set = &scene.glyph_sets[0];
    let n = set.centers.len();
    let k = set.coeffs[0].len();
    let rounded: Vec<Vec<f64>> = set
        .coeffs
        .iter()
        .map(|c| c.iter().map(|&v| v as f32 as f64).collect())
        .collect();
    let fortran: Vec<f64> = (0..k)
        .flat_map(|j| rounded.iter().map(move |c| c[j]))
        .collect();
    npy(&dir.join("f.coeffs.npy"), "<f4", true, &[n, k], &fortran);
    let centers: Vec<f64> = set.centers.iter().flat_map(|c| c.to_array()).collect();
    npy(&dir.join("f.centers.npy"), "<f8", false, &[n, 3], &centers);
    npy(&dir.join("f.scales.npy"), "<f8", false, &[n], &set.scales);
    let numpy_like = json
        .replace("arrays.0.coeffs.npy", "f.coeffs.npy")
        .replace("arrays.0.centers.npy", "f.centers.npy")
        .replace("\"scale\": 1.0", "\"scales\": \"f.scales.npy\"");
    assert!(numpy_like.contains("f.scales.npy"), "{numpy_like}");
    std::fs::write(dir.join("f.json"), numpy_like).expect("scene");
    let mut rounded_scene = scene.clone();
    rounded_scene.glyph_sets[0].coeffs = rounded;
    let loaded = glyphcast::scene::Scene::load(&dir.join("f.json")).expect("loading");
    assert_eq!(
        loaded, rounded_scene,
        "float32 Fortran arrays read as NumPy means them"
    );
}

#[test]
fn bad_arrays_are_refused_naming_scene_field_and_array() {
    let dir = fresh_dir("scene-arrays-bad");
    let scene = |coeffs: &str| {
        format!(
            r#"{{"version": 1, "glyphs": [{{"kind": "tensor", "order": 2,
                "centers": [[0, 0, 0], [2, 0, 0]], "scale": 1, "coeffs": "{coeffs}"}}],
                "camera": {{"eye": [0, -8, 0], "target": [0, 0, 0]}},
                "image": {{"width": 32, "height": 32}}}}"#
        )
    };
    let good = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 2.0, 0.0, 0.0, 1.0, 0.0, 1.0];
    npy(&dir.join("short.npy"), "<f8", false, &[1, 6], &good[..6]);
    npy(&dir.join("wide.npy"), "<f8", false, &[2, 7], &[0.5; 14]);
    let mut nan = good;
    nan[9] = f64::NAN;
    npy(&dir.join("nan.npy"), "<f8", false, &[2, 6], &nan);
    npy(&dir.join("ints.npy"), "<i4", false, &[2, 6], &good);
    // Finite in float64, infinite in the GPU's float32: the glyph would vanish.
    let mut big = good;
    big[9] = 1e39;
    npy(&dir.join("big.npy"), "<f8", false, &[2, 6], &big);
    std::fs::write(dir.join("text.npy"), "not an array").expect("write");
    let mut cut = std::fs::read(dir.join("nan.npy")).expect("read");
    cut.truncate(cut.len() - 8);
    std::fs::write(dir.join("cut.npy"), cut).expect("write");
    let cases = [
        ("short.npy", "shape (2, 6)"),
        ("wide.npy", "shape (2, 6)"),
        ("nan.npy", "row 1, column 3 is NaN"),
        ("ints.npy", "float32 or float64"),
        (
            "big.npy",
            "row 1 (glyph 1), column 3: 1e39 is beyond float32's range",
        ),
        ("text.npy", "not a NumPy .npy file"),
        ("cut.npy", "ends early"),
        ("missing.npy", "missing.npy"),
    ];
    for (array, words) in cases {
        let path = dir.join(format!("{array}.json"));
        std::fs::write(&path, scene(array)).expect("scene");
        let (png, depth) = (dir.join("out.png"), dir.join("out.npy"));
        let out = render(&path, &png, &depth);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{array}: {stderr}");
        let line = stderr
            .lines()
            .find(|l| l.starts_with("error:"))
            .unwrap_or("");
        for word in [text(&path), "glyphs[0].coeffs", array, words] {
            assert!(
                line.contains(word),
                "{array}: '{word}' missing from: {line}"
            );
        }
        assert!(!png.exists() && !depth.exists(), "{array}: no output");
    }
}
