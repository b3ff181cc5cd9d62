//! Coefficient frames, FSL's gradient convention and the recorded SH basis, through the
//! real binary on DIPY's real data (tests/data/dipy), with every variant written here by
//! our own code:
//! - a world-frame FOD (func_coef taken as scanner-axes coefficients, as MRtrix stores
//!   them) stored RAS, LAS (x reversed, affine adjusted) and with the volume axis first
//!   draws the same depth map;
//! - `fit` of small_64D and of its x-flipped copy with the bvec file FSL would keep for
//!   it gives the same glyphs, and the plain voxel reading does not;
//! - `render --sh` takes the basis `fit` recorded, refuses a contradicting `--basis`
//!   unless `--force-basis`, takes an MRtrix file without a record as tournier07, and
//!   asks for `--basis` (exit 2) when a NIfTI records nothing.
use crate::common;

use common::{dipy_data, flipped_in_x, glyphcast, text, write_nifti};
use glam::DMat4;
use glyphcast::io::npy::read_npy_f32;
use glyphcast_dmri::io::image::read_image;
use glyphcast_dmri::io::mif::write::mif_bytes;
use glyphcast_dmri::io::mif::{MifWrite, write_mif};
use glyphcast_dmri::io::nifti::{AffineSource, VoxelToWorld};
use ndarray::ArrayD;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A fresh folder for one test of this file.
fn fresh_dir(name: &str) -> PathBuf {
    common::fresh_dir(&format!("frames/{name}"))
}

fn succeeded(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Renders `args` (a volume and its flags) at 64 x 64 and returns the depth map.
fn depth(dir: &Path, name: &str, args: &[&str]) -> Vec<f32> {
    let (png, npy) = (
        dir.join(format!("{name}.png")),
        dir.join(format!("{name}.npy")),
    );
    let mut all = vec!["render"];
    all.extend(args);
    all.extend(["--width", "64", "--height", "64", "-o", text(&png)]);
    all.extend(["--depth-out", text(&npy)]);
    succeeded(&glyphcast(&all), name);
    let (shape, values) = read_npy_f32(&npy).expect("reading the depth map");
    assert_eq!(shape, vec![64, 64]);
    values
}

/// Pixels hit in one map only, and the largest depth difference where both are hit.
fn compare(a: &[f32], b: &[f32]) -> (usize, f32, usize) {
    let one_only = a
        .iter()
        .zip(b)
        .filter(|(x, y)| x.is_nan() != y.is_nan())
        .count();
    let largest = a
        .iter()
        .zip(b)
        .filter(|(x, y)| !x.is_nan() && !y.is_nan())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f32::max);
    let hits = a.iter().filter(|x| !x.is_nan()).count();
    (one_only, largest, hits)
}

fn map(affine: DMat4) -> VoxelToWorld {
    VoxelToWorld::new(affine, AffineSource::Sform, "test", "affine").expect("a valid affine")
}

/// Writes `data` as a `.mif` with `affine` and the volume axis stored first (layout
/// +1,+2,+3,+0): our writer's header, the layout line changed (same length) and the
/// values reordered so that the 45 coefficients of a voxel are adjacent.
fn write_volume_axis_first(path: &Path, data: &ArrayD<f64>, affine: DMat4) {
    let bytes = mif_bytes(&MifWrite {
        data,
        voxel_to_world: &map(affine),
        keys: &[],
    })
    .expect("header");
    let header_text = String::from_utf8_lossy(&bytes);
    let offset: usize = header_text
        .lines()
        .find_map(|l| l.strip_prefix("file: . "))
        .and_then(|o| o.trim().parse().ok())
        .expect("data offset");
    let mut out = header_text[..offset]
        .replacen("layout: +0,+1,+2,+3", "layout: +1,+2,+3,+0", 1)
        .into_bytes();
    assert_eq!(out.len(), offset, "the layout line keeps its length");
    // Spatial axes i fastest, then j, then k; the coefficients innermost.
    let mut by_voxel = data.clone();
    by_voxel.swap_axes(0, 3); // [c, y, z, x]
    by_voxel.swap_axes(1, 3); // [c, x, z, y]
    by_voxel.swap_axes(2, 3); // [c, x, y, z]
    for &value in by_voxel.t().iter() {
        out.extend_from_slice(&(value as f32).to_le_bytes());
    }
    std::fs::write(path, out).expect("writing the volume-first .mif");
}

/// func_coef's values taken as an FOD in scanner axes, stored RAS, LAS and volume-first,
/// all draw the same depth map with the default frame of `.mif` (world); stored LAS and
/// read in voxel axes instead, the glyphs mirror and the map changes.
#[test]
fn a_world_frame_fod_draws_the_same_whatever_its_storage() {
    let dir = fresh_dir("storage");
    let fod = read_image(&dipy_data("func_coef.nii.gz"))
        .expect("func_coef")
        .data;
    assert_eq!(fod.shape(), &[2, 3, 4, 45]);
    let ras = DMat4::from_cols_array(&[
        2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, -1.0, -2.0, -3.0, 1.0,
    ]);
    let (las_data, las) = flipped_in_x(&fod, ras);
    assert!(las.x_axis.x < 0.0);
    let ras_path = dir.join("ras.mif");
    let las_path = dir.join("las.mif.gz");
    let first_path = dir.join("volume-first.mif");
    let nifti_path = dir.join("ras.nii.gz");
    write_mif(
        &ras_path,
        &MifWrite {
            data: &fod,
            voxel_to_world: &map(ras),
            keys: &[],
        },
    )
    .expect("ras.mif");
    write_mif(
        &las_path,
        &MifWrite {
            data: &las_data,
            voxel_to_world: &map(las),
            keys: &[],
        },
    )
    .expect("las.mif.gz");
    write_volume_axis_first(&first_path, &fod, ras);
    write_nifti(&nifti_path, &fod, ras);
    // The volume-first file reads back as the same values.
    let back = read_image(&first_path).expect("volume-first .mif");
    let largest = (&back.data - &fod.mapv(|v| f64::from(v as f32)))
        .iter()
        .fold(0.0f64, |m, d| m.max(d.abs()));
    assert_eq!(largest, 0.0, "volume-first values");

    let flags = ["--basis", "tournier07", "--legacy", "--slice", "axial:2"];
    let render = |name: &str, path: &Path, extra: &[&str]| {
        let mut args = vec!["--sh", text(path)];
        args.extend(flags);
        args.extend(extra);
        depth(&dir, name, &args)
    };
    let reference = render("ras", &ras_path, &[]);
    for (name, path, extra) in [
        ("las", &las_path, &[][..]),
        ("volume-first", &first_path, &[][..]),
        ("nifti-world", &nifti_path, &["--frame", "world"][..]),
    ] {
        let (one_only, largest, hits) = compare(&reference, &render(name, path, extra));
        assert!(hits > 200, "{name}: the glyphs cover {hits} pixels");
        assert_eq!(one_only, 0, "{name}: coverage differs");
        assert!(largest < 1e-5, "{name}: depth differs by {largest}");
    }
    // Read in voxel axes, the LAS copy's glyphs are mirrored in x: a different picture.
    let mirrored = render("las-voxel", &las_path, &["--frame", "voxel"]);
    let (one_only, largest, _) = compare(&reference, &mirrored);
    assert!(
        one_only > 20 || largest > 0.1,
        "--frame voxel must mirror the glyphs ({one_only} pixels, {largest})"
    );
}

/// The DWI, and its affine, as glyphcast reads them.
/// Fits `dwi` (small_64D's data, or a copy of it) with small_64D's bval/bvec to SH band 4
/// into `output`, with `extra` flags; the fit must succeed.
fn fit_small_64d(dwi: &Path, output: &Path, extra: &[&str]) {
    let (bval, bvec) = (dipy_data("small_64D.bval"), dipy_data("small_64D.bvec"));
    let mut args = vec![
        "fit",
        text(dwi),
        "--bval",
        text(&bval),
        "--bvec",
        text(&bvec),
    ];
    args.extend(["--sh", "--order", "4", "--quiet", "-o", text(output)]);
    args.extend(extra);
    succeeded(&glyphcast(&args), &format!("fit {}", output.display()));
}

fn small_64d() -> (ArrayD<f64>, DMat4) {
    let image = read_image(&dipy_data("small_64D.nii")).expect("small_64D");
    (image.data, image.voxel_to_world.affine)
}

/// small_64D and an x-flipped copy (data reversed along x, x column of the affine
/// negated, origin moved: the same world grid) fitted with the same bvec file draw the
/// same glyphs. That file is what FSL keeps for the copy: FSL's voxel frame is the
/// stored one on an image with a negative determinant and the stored one reversed in x
/// on an image with a positive one; flipping the copy changes the sign of the
/// determinant and reverses x, and the two changes cancel, so FSL's frame of the copy is
/// the original's voxel frame and its bvecs are unchanged (fslswapdim-style flips that
/// change the determinant leave the bvecs alone). Read as plain voxel axes
/// (`--bvec-convention voxel`), the copy's glyphs come out mirrored.
#[test]
fn an_x_flipped_dwi_with_fsl_bvecs_fits_the_same_glyphs() {
    let dir = fresh_dir("fsl");
    let (dwi, affine) = small_64d();
    let determinant = glam::DMat3::from_mat4(affine).determinant();
    let (flipped, flipped_affine) = flipped_in_x(&dwi, affine);
    assert!(determinant * glam::DMat3::from_mat4(flipped_affine).determinant() < 0.0);
    let original_path = dir.join("original.nii.gz");
    let flipped_path = dir.join("flipped.nii.gz");
    write_nifti(&original_path, &dwi, affine);
    write_nifti(&flipped_path, &flipped, flipped_affine);
    let outputs = [
        ("original", &original_path, &[][..]),
        ("flipped", &flipped_path, &[][..]),
        (
            "flipped-voxel",
            &flipped_path,
            &["--bvec-convention", "voxel"][..],
        ),
        ("original-mif", &original_path, &[][..]),
    ];
    let mut maps = Vec::new();
    for (name, input, extra) in outputs {
        let ending = if name.ends_with("mif") {
            "mif"
        } else {
            "nii.gz"
        };
        let coefficients = dir.join(format!("{name}-sh.{ending}"));
        fit_small_64d(input, &coefficients, extra);
        // No --basis: the file records it (see the basis tests below).
        let args = ["--sh", text(&coefficients), "--slice", "axial:5"];
        maps.push((name, depth(&dir, name, &args)));
    }
    let reference = &maps[0].1;
    let mut differences = Vec::new();
    for (name, map) in &maps[1..] {
        let (one_only, largest, hits) = compare(reference, map);
        assert!(hits > 200, "{name}: the glyphs cover {hits} pixels");
        differences.push((*name, one_only, largest));
    }
    eprintln!("pixels hit in one map only, largest depth difference: {differences:?}");
    for (name, one_only, largest) in [differences[0], differences[2]] {
        // Rounding in the fit (the signal is float32) may move a silhouette pixel.
        assert!(
            one_only <= 4,
            "{name}: {one_only} pixels differ in coverage"
        );
        assert!(largest < 1e-3, "{name}: depth differs by {largest}");
    }
    let (_, one_only, largest) = differences[1];
    assert!(
        one_only > 50 || largest > 0.5,
        "read as plain voxel axes the flipped copy's glyphs mirror ({one_only}, {largest})"
    );
}

/// The default bvec convention says where it negates x (a positive determinant), which
/// DIPY does not do: a note on the x-flipped copy, none on small_64D itself (negative) or
/// when the convention is named. And `--basis mrtrix` on a NIfTI without `--frame` says
/// that a NIfTI from MRtrix's mrconvert needs `--frame world`; each note once.
#[test]
fn readings_other_tools_differ_on_are_noted_once() {
    let dir = fresh_dir("notes");
    let (dwi, affine) = small_64d();
    let (flipped, flipped_affine) = flipped_in_x(&dwi, affine);
    let (original_path, flipped_path) = (dir.join("original.nii"), dir.join("flipped.nii"));
    write_nifti(&original_path, &dwi, affine);
    write_nifti(&flipped_path, &flipped, flipped_affine);
    let (bval, bvec) = (dipy_data("small_64D.bval"), dipy_data("small_64D.bvec"));
    let notes = |args: &[&str]| {
        let out = glyphcast(args);
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{args:?}: {stderr}");
        let notes: Vec<String> = stderr
            .lines()
            .filter(|l| l.starts_with("note:"))
            .map(str::to_string)
            .collect();
        notes
    };
    let fit = |dwi: &Path, extra: &[&str]| {
        let out = dir.join("dti.nii");
        let mut args = vec![
            "fit",
            text(dwi),
            "--bval",
            text(&bval),
            "--bvec",
            text(&bvec),
        ];
        args.extend(["--order", "2", "-o", text(&out)]);
        args.extend(extra);
        let found = notes(&args);
        std::fs::remove_file(&out).expect("the fit's output");
        found
    };
    let flipped_notes = fit(&flipped_path, &[]);
    assert_eq!(flipped_notes.len(), 1, "{flipped_notes:?}");
    assert!(
        flipped_notes[0].contains("flipped.nii")
            && flipped_notes[0].contains("--bvec-convention voxel"),
        "{flipped_notes:?}"
    );
    assert!(fit(&flipped_path, &["--bvec-convention", "fsl"]).is_empty());
    assert!(fit(&original_path, &[]).is_empty());

    let fod = dipy_data("func_coef.nii.gz");
    let render = |extra: &[&str]| {
        let png = dir.join("fod.png");
        let mut args = vec![
            "render",
            "--sh",
            text(&fod),
            "--width",
            "64",
            "--height",
            "64",
        ];
        args.extend(["-o", text(&png)]);
        args.extend(extra);
        let found = notes(&args);
        std::fs::remove_file(&png).expect("the image");
        found
    };
    let mrtrix = render(&["--basis", "mrtrix"]);
    assert_eq!(mrtrix.len(), 1, "{mrtrix:?}");
    assert!(mrtrix[0].contains("--frame world"), "{mrtrix:?}");
    assert!(render(&["--basis", "mrtrix", "--frame", "voxel"]).is_empty());
    assert!(render(&["--basis", "tournier07", "--legacy"]).is_empty());
    assert!(render(&["--basis", "dipy-new"]).is_empty());
}

/// A file glyphcast wrote says what it holds, and is not read as something else: an SH
/// fit as tensors or peaks, a tensor fit as SH, peaks as tensors; each refusal names the
/// file and the field (exit 1) and what to read it as; `glyphcast peaks` of a tensor fit
/// likewise.
#[test]
fn what_a_file_records_it_holds_is_not_read_as_another_kind() {
    let dir = fresh_dir("content");
    let dwi = dipy_data("small_64D.nii");
    let sh = dir.join("sh.nii");
    fit_small_64d(&dwi, &sh, &["--basis", "dipy"]);
    let dti = common::fit_dti_small_64d(&dir);
    let peaks = dir.join("peaks.nii");
    let run = glyphcast(&[
        "peaks",
        text(&sh),
        "--count",
        "2",
        "--quiet",
        "-o",
        text(&peaks),
    ]);
    succeeded(&run, "peaks");
    let cases: [(&[&str], &str); 4] = [
        (
            &["--tensor", text(&sh), "--order", "4"],
            "sh.nii: descrip: records SH coefficients",
        ),
        (
            &["--sh", text(&dti)],
            "dti.nii.gz: descrip: records a symmetric tensor of order 2",
        ),
        (
            &["--tensor", text(&peaks), "--order", "2"],
            "peaks.nii: descrip: records fibre peaks",
        ),
        (&["--sh", text(&sh), "--peaks", text(&sh)], "not peaks"),
    ];
    for (args, words) in cases {
        let (code, error) = render_failure(&dir, args);
        assert_eq!(code, 1, "{args:?}: {error}");
        assert!(error.contains(words), "{args:?}: {error}");
    }
    let out = dir.join("peaks-of-dti.nii");
    let run = glyphcast(&["peaks", text(&dti), "--basis", "dipy", "-o", text(&out)]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("records a symmetric tensor"), "{stderr}");
    assert!(!out.exists());
}

/// Runs `render ARGS` into `dir`, expecting failure: the exit code and the one error line.
fn render_failure(dir: &Path, args: &[&str]) -> (i32, String) {
    let png = dir.join("failed.png");
    let mut all = vec!["render"];
    all.extend(args);
    all.extend(["--width", "32", "--height", "32", "-o", text(&png)]);
    let out = glyphcast(&all);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!png.exists(), "{args:?}: no output on failure");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{args:?}: one error line:\n{stderr}");
    (out.status.code().unwrap_or(-1), errors[0].to_string())
}

/// `fit` records the basis; `render` takes it without --basis, agrees with a matching
/// --basis, refuses another naming the file and the field, and draws it with
/// --force-basis. For NIfTI (DIPY's basis) the field is descrip, for .mif (MRtrix's, the
/// only one a .mif is written in) comments.
#[test]
fn render_takes_the_basis_fit_recorded_and_refuses_a_contradiction() {
    let dir = fresh_dir("basis");
    let dwi = dipy_data("small_64D.nii");
    struct Case {
        output: &'static str,
        field: &'static str,
        basis: &'static str,
        spelled: &'static [&'static str],
        other: &'static str,
        other_named: &'static str,
    }
    let cases = [
        Case {
            output: "fitted.nii.gz",
            field: "descrip",
            basis: "dipy",
            spelled: &["--basis", "descoteaux07", "--legacy"],
            other: "mrtrix",
            other_named: "descoteaux07 --legacy",
        },
        Case {
            output: "fitted.mif",
            field: "comments",
            basis: "mrtrix",
            spelled: &["--basis", "tournier07"],
            other: "dipy",
            other_named: "tournier07",
        },
    ];
    for case in cases {
        let fitted = dir.join(case.output);
        fit_small_64d(&dwi, &fitted, &["--basis", case.basis]);
        let volume = ["--sh", text(&fitted), "--slice", "axial:5"];
        let with = |extra: &[&'static str]| {
            let mut args: Vec<&str> = volume.to_vec();
            args.extend(extra);
            args
        };
        let output = case.output;
        let recorded = depth(&dir, "recorded", &volume);
        let (one_only, largest, _) = compare(
            &recorded,
            &depth(&dir, "same", &with(&["--basis", case.basis])),
        );
        assert_eq!(
            (one_only, largest),
            (0, 0.0),
            "{output}: --basis {} agrees",
            case.basis
        );
        depth(&dir, "spelled", &with(case.spelled));
        let (code, error) = render_failure(&dir, &with(&["--basis", case.other]));
        assert_eq!(code, 1, "{error}");
        assert!(
            error.contains(&format!("{}: {}:", text(&fitted), case.field))
                && error.contains(case.other_named)
                && error.contains("--force-basis"),
            "{error}"
        );
        let forced = depth(
            &dir,
            "forced",
            &with(&["--basis", case.other, "--force-basis"]),
        );
        let (one_only, largest, _) = compare(&recorded, &forced);
        assert!(
            one_only > 0 || largest > 0.0,
            "{output}: another basis draws other glyphs"
        );
    }
}

/// A fit in any basis but MRtrix's own is not written to a `.mif`: MRtrix reads every
/// `.mif`'s SH coefficients as tournier07, whatever glyphcast would record beside them.
/// Refused before the fit (a usage error naming the output and the basis); nothing is
/// written. NIfTI takes every basis.
#[test]
fn a_mif_is_fitted_in_mrtrix_basis_only() {
    let dir = fresh_dir("mif_basis");
    let dwi = dipy_data("small_64D.nii");
    let (bval, bvec) = (dipy_data("small_64D.bval"), dipy_data("small_64D.bvec"));
    for basis in [
        &["--basis", "dipy"][..],
        &["--basis", "descoteaux07"],
        &["--basis", "tournier07", "--legacy"],
    ] {
        for odf in [&["--sh"][..], &["--odf", "csa"]] {
            let mif = dir.join("refused.mif");
            let mut args = vec![
                "fit",
                text(&dwi),
                "--bval",
                text(&bval),
                "--bvec",
                text(&bvec),
            ];
            args.extend(odf);
            args.extend(["--order", "4", "--quiet", "-o", text(&mif)]);
            args.extend(basis);
            let out = glyphcast(&args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
            assert!(
                stderr.contains(text(&mif)) && stderr.contains("tournier07"),
                "{args:?}: {stderr}"
            );
            assert!(!mif.exists(), "{args:?}: nothing written");
        }
    }
    fit_small_64d(&dwi, &dir.join("dipy.nii"), &["--basis", "dipy"]);
    fit_small_64d(&dwi, &dir.join("mrtrix.mif"), &["--basis", "mrtrix"]);
}

/// Writes func_coef as a `.mif` with its affine and the header line `key: value`;
/// returns its values and affine.
fn func_coef_as_mif(path: &Path, (key, value): (&str, &str)) -> (ArrayD<f64>, DMat4) {
    let fod = read_image(&dipy_data("func_coef.nii.gz")).expect("func_coef");
    let (values, affine) = (fod.data, fod.voxel_to_world.affine);
    let keys = [(key, value.to_string())];
    let image = MifWrite {
        data: &values,
        voxel_to_world: &map(affine),
        keys: &keys,
    };
    write_mif(path, &image).expect("writing the .mif");
    (values, affine)
}

/// A `.mif`'s basis is read from `comments` and from `glyphcast_sh_basis` alike: a key
/// alone is the basis (func_coef under "descoteaux07 legacy" draws as with that --basis);
/// a name glyphcast does not know, in either, and two records that disagree are refused
/// naming the file and the field, never drawn as MRtrix's tournier07.
#[test]
fn a_mif_basis_record_is_read_from_either_field_or_refused() {
    let dir = fresh_dir("mif_basis_record");
    let keyed = dir.join("keyed.mif");
    func_coef_as_mif(&keyed, ("glyphcast_sh_basis", "descoteaux07 legacy"));
    let volume = ["--sh", text(&keyed), "--slice", "axial:2"];
    let recorded = depth(&dir, "keyed", &volume);
    let mut named = volume.to_vec();
    named.extend(["--basis", "dipy"]);
    let (one_only, largest, hits) = compare(&recorded, &depth(&dir, "named", &named));
    assert!(hits > 100);
    assert_eq!((one_only, largest), (0, 0.0), "the key's basis is drawn");
    let mut contradicted = volume.to_vec();
    contradicted.extend(["--basis", "mrtrix"]);
    let (code, error) = render_failure(&dir, &contradicted);
    assert_eq!(code, 1, "{error}");
    assert!(error.contains("keyed.mif: glyphcast_sh_basis:"), "{error}");

    let func_coef = read_image(&dipy_data("func_coef.nii.gz")).expect("func_coef");
    let (values, affine) = (func_coef.data, func_coef.voxel_to_world.affine);
    // (file name, header lines, words of the refusal)
    type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a str);
    let cases: [Case; 3] = [
        (
            "typo",
            &[(
                "comments",
                "glyphcast fit: SH band 8 descoteax07 lambda 0.006",
            )],
            "comments: records the SH basis 'descoteax07'",
        ),
        (
            "unknown",
            &[("glyphcast_sh_basis", "foo07")],
            "glyphcast_sh_basis: records the SH basis 'foo07'",
        ),
        (
            "disagree",
            &[
                (
                    "comments",
                    "glyphcast fit: SH band 8 tournier07 lambda 0.006",
                ),
                ("glyphcast_sh_basis", "descoteaux07"),
            ],
            "glyphcast_sh_basis: records the SH basis descoteaux07, but comments records tournier07",
        ),
    ];
    for (name, keys, words) in cases {
        let mif = dir.join(format!("{name}.mif"));
        let keys: Vec<(&str, String)> = keys.iter().map(|(k, v)| (*k, v.to_string())).collect();
        let image = MifWrite {
            data: &values,
            voxel_to_world: &map(affine),
            keys: &keys,
        };
        write_mif(&mif, &image).expect("writing the .mif");
        let (code, error) = render_failure(&dir, &["--sh", text(&mif), "--slice", "axial:2"]);
        assert_eq!(code, 1, "{name}: {error}");
        assert!(error.contains(words), "{name}: {error}");
    }
}

/// Without a record: an MRtrix file is tournier07 (MRtrix's basis), a NIfTI file needs
/// --basis (a usage error, exit 2, naming the file).
#[test]
fn without_a_record_mrtrix_means_tournier07_and_nifti_needs_basis() {
    let dir = fresh_dir("unrecorded");
    let mif = dir.join("plain.mif");
    let (values, affine) = func_coef_as_mif(&mif, ("comments", "no basis here"));
    let volume = ["--sh", text(&mif), "--slice", "axial:2"];
    let default = depth(&dir, "default", &volume);
    let mut tournier = volume.to_vec();
    tournier.extend(["--basis", "tournier07"]);
    let (one_only, largest, hits) = compare(&default, &depth(&dir, "tournier", &tournier));
    assert!(hits > 100);
    assert_eq!((one_only, largest), (0, 0.0), "a plain .mif is tournier07");
    let mut legacy = volume.to_vec();
    legacy.extend(["--basis", "tournier07", "--legacy"]);
    let (one_only, largest, _) = compare(&default, &depth(&dir, "legacy", &legacy));
    assert!(one_only > 0 || largest > 0.0, "the legacy variant differs");

    let nifti = dir.join("plain.nii.gz");
    write_nifti(&nifti, &values, affine);
    let (code, error) = render_failure(&dir, &["--sh", text(&nifti)]);
    assert_eq!(code, 2, "{error}");
    assert!(
        error.contains("--basis") && error.contains(text(&nifti)) && error.contains("descrip"),
        "{error}"
    );
}

/// The frame of a volume is its file's unless --frame says otherwise; a bad --frame or
/// a bad glyphcast_frame key is one clear error.
#[test]
fn bad_frames_are_refused() {
    let dir = fresh_dir("bad-frame");
    let mif = dir.join("odd.mif");
    func_coef_as_mif(&mif, ("glyphcast_frame", "scanner"));
    let (code, error) = render_failure(&dir, &["--sh", text(&mif)]);
    assert_eq!(code, 1, "{error}");
    assert!(error.contains("odd.mif: glyphcast_frame:"), "{error}");
    let args = [
        "--sh",
        text(&mif),
        "--frame",
        "scanner",
        "--basis",
        "mrtrix",
    ];
    let (_, error) = render_failure(&dir, &args);
    assert!(error.contains("expected voxel or world"), "{error}");
}

/// On an oblique grid, `fit -o X.mif` writes the glyphs in scanner axes (MRtrix's frame:
/// the coefficients differ from the voxel-axes NIfTI of the same fit) and both files draw
/// the same glyphs with their default frames.
#[test]
fn fit_writes_mif_in_scanner_axes_on_an_oblique_grid() {
    let dir = fresh_dir("oblique");
    let (dwi, affine) = small_64d();
    let turn = DMat4::from_rotation_z(0.5) * DMat4::from_rotation_x(0.2);
    let oblique = dir.join("oblique.nii.gz");
    write_nifti(&oblique, &dwi, turn * affine);
    let mut maps = Vec::new();
    let mut coefficients = Vec::new();
    for name in ["sh.nii.gz", "sh.mif"] {
        let output = dir.join(name);
        fit_small_64d(&oblique, &output, &[]);
        coefficients.push(read_image(&output).expect("reading the fit").data);
        let render = ["--sh", text(&output), "--slice", "axial:5"];
        maps.push(depth(&dir, name, &render));
    }
    let (voxel, world) = (&coefficients[0], &coefficients[1]);
    assert_eq!(voxel.shape(), world.shape());
    let scale = voxel.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let moved = voxel
        .iter()
        .zip(world.iter())
        .filter(|(v, w)| (*v - *w).abs() > 1e-3 * scale)
        .count();
    assert!(moved > voxel.len() / 4, "only {moved} coefficients changed");
    let (one_only, largest, hits) = compare(&maps[0], &maps[1]);
    assert!(hits > 200, "the glyphs cover {hits} pixels");
    assert!(one_only <= 4, "{one_only} pixels differ in coverage");
    assert!(largest < 1e-3, "depth differs by {largest}");
}
