//! `descoteaux07` alone names two bases: DIPY 1.x writes its legacy variant unless told
//! otherwise, and calls the non-legacy one by the same name. On a file that records no
//! basis the bare name is refused by every command that reads SH coefficients, naming
//! the file and both choices; the aliases and `--legacy` draw, and the summary names the
//! basis and variant drawn. A file that records its basis decides the variant.
use crate::common;

use common::{dipy_data, glyphcast, text};
use glyphcast_dmri::io::image::read_image;
use glyphcast_dmri::io::mif::{MifWrite, write_mif};
use glyphcast_dmri::io::nifti::{AffineSource, VoxelToWorld};
use std::path::{Path, PathBuf};
use std::process::Output;

fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("basis_names/{name}"))
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `glyphcast render --sh FILE` of a small image with `extra`, written to `png`.
fn render(file: &Path, png: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        "--sh",
        text(file),
        "--slice",
        "axial:2",
        "--width",
        "64",
        "--height",
        "64",
        "-o",
        text(png),
    ];
    args.extend(extra);
    glyphcast(&args)
}

/// The refusal of a bare `descoteaux07`: a usage error naming the file and both choices.
fn assert_refused(out: &Output, file: &str, args: &str) {
    let message = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{args}: {message}");
    assert!(!message.contains("panicked"), "{args}: {message}");
    for word in [file, "--basis dipy", "--legacy", "--basis dipy-new"] {
        assert!(message.contains(word), "{args}: '{word}' not in {message}");
    }
}

/// func_coef (DIPY's SH test image, descoteaux07 legacy) records no basis: a bare
/// `--basis descoteaux07` is refused by render, peaks and qc, and nothing is written;
/// `--basis dipy` and `--basis descoteaux07 --legacy` draw the same picture, and
/// `--basis dipy-new` another, each summary naming the basis and variant.
#[test]
fn a_bare_descoteaux07_on_a_file_without_a_record_is_refused() {
    let dir = fresh_dir("refused");
    let fod = dipy_data("func_coef.nii.gz");
    let png = dir.join("bare.png");
    let out = render(&fod, &png, &["--basis", "descoteaux07"]);
    assert_refused(&out, "func_coef.nii.gz", "render");
    assert!(!png.exists(), "the refused render wrote {}", png.display());
    // Any case, as every basis name.
    let out = render(&fod, &png, &["--basis", "Descoteaux07"]);
    assert_refused(&out, "func_coef.nii.gz", "render, other case");

    let peaks = dir.join("peaks.nii");
    let out = glyphcast(&[
        "peaks",
        text(&fod),
        "--basis",
        "descoteaux07",
        "-o",
        text(&peaks),
    ]);
    assert_refused(&out, "func_coef.nii.gz", "peaks");
    assert!(!peaks.exists());

    let set = dir.join("qc");
    let out = glyphcast(&[
        "qc",
        text(&fod),
        "--basis",
        "descoteaux07",
        "--quiet",
        "-o",
        text(&set),
    ]);
    assert_refused(&out, "func_coef.nii.gz", "qc");
    assert!(!set.exists());

    let drawn = |name: &str, extra: &[&str], summary: &str| {
        let png = dir.join(name);
        let out = render(&fod, &png, extra);
        let message = stderr(&out);
        assert!(out.status.success(), "{extra:?}: {message}");
        let line = format!("SH basis: {}: {summary}\n", text(&fod));
        assert!(
            message.contains(&line),
            "{extra:?}: '{line}' not in {message}"
        );
        std::fs::read(&png).expect("the image")
    };
    let dipy = drawn("dipy.png", &["--basis", "dipy"], "descoteaux07, legacy");
    let legacy = drawn(
        "legacy.png",
        &["--basis", "descoteaux07", "--legacy"],
        "descoteaux07, legacy",
    );
    let new = drawn("new.png", &["--basis", "dipy-new"], "descoteaux07");
    assert_eq!(dipy, legacy, "--basis dipy is descoteaux07 --legacy");
    assert_ne!(dipy, new, "the two variants draw different glyphs");
}

/// A file that records its basis says which variant it is in: a bare `descoteaux07`
/// is read as recorded (a `.mif` under "descoteaux07"), or refused as a contradiction
/// of a legacy record, as any other basis that differs from the record.
#[test]
fn a_recorded_basis_decides_the_variant_of_a_bare_descoteaux07() {
    let dir = fresh_dir("recorded");
    let source = read_image(&dipy_data("func_coef.nii.gz")).expect("func_coef");
    let map = VoxelToWorld::new(
        source.voxel_to_world.affine,
        AffineSource::Sform,
        "test",
        "affine",
    )
    .expect("a valid affine");
    let write = |name: &str, record: &str| {
        let path = dir.join(name);
        let keys = [("glyphcast_sh_basis", record.to_string())];
        let image = MifWrite {
            data: &source.data,
            voxel_to_world: &map,
            keys: &keys,
        };
        write_mif(&path, &image).expect("writing the .mif");
        path
    };
    let plain = write("plain.mif", "descoteaux07");
    let out = render(&plain, &dir.join("plain.png"), &["--basis", "descoteaux07"]);
    let message = stderr(&out);
    assert!(out.status.success(), "{message}");
    assert!(
        message.contains(&format!("SH basis: {}: descoteaux07\n", text(&plain))),
        "{message}"
    );

    let legacy = write("legacy.mif", "descoteaux07 legacy");
    let out = render(
        &legacy,
        &dir.join("legacy.png"),
        &["--basis", "descoteaux07"],
    );
    let message = stderr(&out);
    // The conflict with the file's record is bad data (exit 1), as before.
    assert_eq!(out.status.code(), Some(1), "{message}");
    assert!(
        message.contains("legacy.mif") && message.contains("--force-basis"),
        "{message}"
    );
    // Forced, the record no longer decides: the bare name is refused as on a file
    // without one.
    let out = render(
        &legacy,
        &dir.join("forced.png"),
        &["--basis", "descoteaux07", "--force-basis"],
    );
    assert_refused(&out, "legacy.mif", "forced");
}
