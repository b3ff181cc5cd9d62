//! Fibre ODFs on real DWI (DIPY's small_64D: one b=0 and 64 directions at b ~ 1000):
//! `fit --odf csd|csa|qball` and `peaks`.
//!
//! - CSA and Q-ball coefficients agree with DIPY's `CsaOdfModel` and `QballModel`, and
//!   CSD's peaks with those of DIPY's `ConstrainedSphericalDeconvModel`, read from
//!   `tests/data/dipy/odf-dipy.json` (computed once by `tools/dipy_fixtures.py`, which records
//!   the DIPY version and every parameter; CI does not run DIPY).
//! - CSD and CSA peaks follow the DTI principal direction where FA > 0.6, which the
//!   signal's own SH series does not (its largest lobe lies across the fibre).
//! - The command line writes the basis into the header, `peaks` writes MRtrix's layout,
//!   and bad input fails cleanly.
use crate::common;

use common::{
    DwiFiles, axis_angle, dipy_data, expect_failure, fit_small_64d, fresh_dir, glyphcast,
    largest_difference, numbers, text,
};
use glam::DVec3;
use glyphcast::glyph::sh::{sh_count, sh_eval};
use glyphcast::scene::ShBasis;
use glyphcast_dmri::fit::csd::{CsdFitter, CsdParameters};
use glyphcast_dmri::fit::dti::DiffusionTensor;
use glyphcast_dmri::fit::peaks::{PeakFinder, PeakOptions};
use glyphcast_dmri::fit::response::{DEFAULT_RESPONSE_FA, estimate_response};
use glyphcast_dmri::fit::{
    CsdAlgorithm, FitInputs, FitModel, OdfMethod, OdfModel, Response, fit, fit_with_response,
};
use ndarray::Array4;
use nifti::{IntoNdArray, NiftiObject, ReaderOptions};
use serde_json::Value;
use std::path::Path;

/// DIPY's default basis: descoteaux07, legacy.
const DIPY_BASIS: (ShBasis, bool) = (ShBasis::Descoteaux07, true);

fn inputs() -> FitInputs {
    // The b-vectors as stored, as DIPY reads them (no --bvec-convention transform).
    DwiFiles::small_64d().inputs()
}

fn fixture() -> Value {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data/dipy/odf-dipy.json");
    let text = std::fs::read_to_string(&path).expect("reading the DIPY fixture");
    serde_json::from_str(&text).expect("parsing the DIPY fixture")
}

fn voxel_of(record: &Value) -> [usize; 3] {
    let v = numbers(&record["voxel"]);
    [v[0] as usize, v[1] as usize, v[2] as usize]
}

fn series(volume: &Array4<f64>, [x, y, z]: [usize; 3]) -> Vec<f64> {
    volume.slice(ndarray::s![x, y, z, ..]).to_vec()
}

fn odf_model(method: OdfMethod, band: u32, lambda: f64) -> FitModel {
    FitModel::Odf(OdfModel {
        method,
        band,
        basis: DIPY_BASIS.0,
        legacy: DIPY_BASIS.1,
        lambda,
        tau: 0.1,
        // The DIPY fixture's algorithm; `fit`'s default is MRtrix's (tests/csd_mrtrix.rs).
        csd: CsdAlgorithm::Dipy,
    })
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    }
}

/// DTI of every voxel: FA and principal direction (None where not fitted).
fn dti(inputs: &FitInputs) -> Array4<f64> {
    fit(inputs, &FitModel::Tensor { order: 2 }, &mut |_| {}).expect("DTI fit")
}

fn tensor_at(dti: &Array4<f64>, voxel: [usize; 3]) -> Option<DiffusionTensor> {
    DiffusionTensor::from_coefficients(&series(dti, voxel))
}

#[test]
fn csa_and_qball_coefficients_match_dipy() {
    let fixture = fixture();
    let inputs = inputs();
    for (key, method) in [("csa", OdfMethod::Csa), ("qball", OdfMethod::Qball)] {
        let params = &fixture[key];
        let band = params["sh_order_max"].as_u64().expect("order") as u32;
        let lambda = params["smooth"].as_f64().expect("smooth");
        let ours = fit(&inputs, &odf_model(method, band, lambda), &mut |_| {}).expect(key);
        let mut worst: f64 = 0.0;
        for record in fixture["voxels"].as_array().expect("voxels") {
            let voxel = voxel_of(record);
            let theirs = numbers(&record[key]);
            let mine = series(&ours, voxel);
            assert_eq!(mine.len(), theirs.len());
            let (error, scale) = largest_difference(&mine, &theirs);
            // Relative to the voxel's largest coefficient; DIPY normalises in float32.
            assert!(
                error <= 1e-4 * scale,
                "{key} at {voxel:?}: error {error:e} of {scale:e}\nours {mine:?}\ndipy {theirs:?}"
            );
            worst = worst.max(error / scale);
        }
        eprintln!(
            "{key}: worst relative difference from DIPY {} : {worst:.2e}",
            fixture["dipy_version"]
        );
    }
}

/// Angles (degrees) between CSD peaks of `csd` and DIPY's in the fixture's voxels with
/// FA above the test's threshold: (first peak to first peak, each of DIPY's peaks to the
/// nearest of ours where both find as many).
fn csd_peak_angles(fixture: &Value, csd: &Array4<f64>, band: u32) -> (Vec<f64>, Vec<f64>) {
    let finder = PeakFinder::new(band, DIPY_BASIS.0, DIPY_BASIS.1, PeakOptions::default())
        .expect("peak finder");
    let fa_limit = fixture["dti"]["fa_threshold_of_the_test"]
        .as_f64()
        .expect("FA");
    let (mut first, mut all) = (Vec::new(), Vec::new());
    for record in fixture["voxels"].as_array().expect("voxels") {
        if record["fa"].as_f64().expect("fa") <= fa_limit {
            continue;
        }
        let voxel = voxel_of(record);
        let peaks = finder.find(&series(csd, voxel));
        let theirs: Vec<DVec3> = record["csd_peak_directions"]
            .as_array()
            .expect("peaks")
            .iter()
            .map(|d| DVec3::from_slice(&numbers(d)))
            .collect();
        assert!(!peaks.is_empty() && !theirs.is_empty(), "{voxel:?}");
        first.push(axis_angle(peaks[0].direction, theirs[0]));
        if peaks.len() == theirs.len() {
            for d in &theirs {
                let nearest = peaks
                    .iter()
                    .map(|p| axis_angle(p.direction, *d))
                    .fold(f64::INFINITY, f64::min);
                all.push(nearest);
            }
        }
    }
    (first, all)
}

fn summary(angles: &[f64]) -> String {
    format!(
        "{} peaks, median {:.2}, worst {:.2} degrees",
        angles.len(),
        median(angles.to_vec()),
        angles.iter().copied().fold(0.0, f64::max)
    )
}

/// DIPY's response as the fixture records it (sqrt(4 pi/(2l+1)) r_l per band).
fn dipy_response(fixture: &Value) -> Response {
    let rh = numbers(&fixture["csd"]["response_rh"]);
    let zonal = rh
        .iter()
        .enumerate()
        .map(|(i, r)| r / (4.0 * std::f64::consts::PI / (4.0 * i as f64 + 1.0)).sqrt())
        .collect();
    Response { zonal }
}

/// The deconvolution itself: given DIPY's response and DIPY's constraint directions, the
/// fODF coefficients are DIPY's to 1e-4 of the voxel's largest, and so are the peaks.
#[test]
fn csd_with_dipys_response_and_constraint_matches_dipy() {
    let fixture = fixture();
    let params = &fixture["csd"];
    let band = params["sh_order_max"].as_u64().expect("order") as u32;
    let lambda = params["lambda_"].as_f64().expect("lambda");
    let tau = params["tau"].as_f64().expect("tau");
    let constraint: Vec<DVec3> = params["constraint_directions"]
        .as_array()
        .expect("directions")
        .iter()
        .map(|d| DVec3::from_slice(&numbers(d)))
        .collect();
    let inputs = inputs();
    let weighted = inputs.gradients.weighted();
    let directions: Vec<DVec3> = weighted.iter().map(|w| w.2).collect();
    let fitter = CsdFitter::with_constraint(
        band,
        DIPY_BASIS,
        &directions,
        &dipy_response(&fixture),
        CsdParameters { lambda, tau },
        &constraint,
    )
    .expect("CSD");
    let mut csd = Array4::zeros((10, 10, 10, sh_count(band)));
    let mut worst: f64 = 0.0;
    for record in fixture["voxels"].as_array().expect("voxels") {
        let [x, y, z] = voxel_of(record);
        let signal: Vec<f64> = weighted
            .iter()
            .map(|w| inputs.dwi.signal[[x, y, z, w.0]])
            .collect();
        let mut mine = vec![0.0; sh_count(band)];
        fitter.fit_into(&signal, &mut mine);
        let theirs = numbers(&record["csd"]);
        let (error, scale) = largest_difference(&mine, &theirs);
        assert!(
            error <= 1e-4 * scale,
            "CSD at {:?}: error {error:e} of {scale:e}",
            [x, y, z]
        );
        worst = worst.max(error / scale);
        csd.slice_mut(ndarray::s![x, y, z, ..])
            .iter_mut()
            .zip(&mine)
            .for_each(|(o, v)| *o = *v);
    }
    let (first, all) = csd_peak_angles(&fixture, &csd, band);
    eprintln!(
        "CSD with DIPY {}'s response and constraint: coefficients within {worst:.2e} of the largest; first peaks {}; all peaks {}",
        fixture["dipy_version"],
        summary(&first),
        summary(&all)
    );
    assert!(first.len() >= 20, "too few high-FA voxels in the fixture");
    assert!(all.len() >= first.len(), "peak counts differ too often");
    assert!(all.iter().all(|&a| a <= 5.0), "{all:?}");
}

/// `fit --odf csd` as it runs (geodesic constraint directions; DIPY's or its own
/// response) against DIPY's peaks. Where a voxel's lobe is a blend of two fibres its
/// maximum is poorly determined: DIPY's own peak at voxel [0, 2, 1] moves by 6.5 degrees
/// when only its constraint sphere changes (symmetric362 to repulsion724, measured with
/// DIPY 1.12.1), so single voxels may differ by more than 5 degrees; the bulk must not.
#[test]
fn csd_peaks_match_dipy_where_fa_is_high() {
    let fixture = fixture();
    let params = &fixture["csd"];
    let band = params["sh_order_max"].as_u64().expect("order") as u32;
    let lambda = params["lambda_"].as_f64().expect("lambda");
    let inputs = inputs();
    let model = odf_model(OdfMethod::Csd, band, lambda);
    let response = dipy_response(&fixture);
    for (name, response) in [
        ("DIPY's response", Some(&response)),
        ("the estimated response", None),
    ] {
        let (csd, _) = fit_with_response(&inputs, &model, response, &mut |_| {}).expect("CSD");
        let (first, all) = csd_peak_angles(&fixture, &csd, band);
        eprintln!(
            "CSD with {name}: first peaks {}; all peaks {}",
            summary(&first),
            summary(&all)
        );
        assert!(first.len() >= 20, "too few high-FA voxels in the fixture");
        let within = all.iter().filter(|&&a| a <= 5.0).count();
        assert!(median(first.clone()) <= 2.0, "{name}: {first:?}");
        assert!(within as f64 >= 0.9 * all.len() as f64, "{name}: {all:?}");
    }
}

/// The measurement: in voxels with FA > 0.6, the largest lobe of the signal's
/// SH series lies across the fibre, while CSD and CSA peaks follow DTI's principal
/// direction (median within 15 degrees).
#[test]
fn fibre_odf_peaks_follow_the_dti_direction() {
    let inputs = inputs();
    let dti = dti(&inputs);
    let signal_model = FitModel::Sh {
        band: 8,
        basis: DIPY_BASIS.0,
        legacy: DIPY_BASIS.1,
        lambda: 0.006,
    };
    let cases = [
        ("signal SH", signal_model, 8),
        ("CSD", odf_model(OdfMethod::Csd, 8, 1.0), 8),
        ("CSA", odf_model(OdfMethod::Csa, 6, 0.006), 6),
    ];
    let options = PeakOptions {
        count: 1,
        ..PeakOptions::default()
    };
    let [nx, ny, nz] = inputs.dwi.spatial_shape();
    let mut medians = Vec::new();
    for (name, model, band) in cases {
        let volume = fit(&inputs, &model, &mut |_| {}).expect(name);
        let finder = PeakFinder::new(band, DIPY_BASIS.0, DIPY_BASIS.1, options).unwrap();
        let mut angles = Vec::new();
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let Some(t) = tensor_at(&dti, [x, y, z]) else {
                        continue;
                    };
                    if t.fractional_anisotropy() <= 0.6 || t.eigenvalues[2] <= 0.0 {
                        continue;
                    }
                    let peaks = finder.find(&series(&volume, [x, y, z]));
                    let angle = peaks
                        .first()
                        .map_or(90.0, |p| axis_angle(p.direction, t.principal));
                    angles.push(angle);
                }
            }
        }
        let m = median(angles.clone());
        eprintln!(
            "{name}: median angle to the DTI direction {m:.2} degrees over {} voxels with FA > 0.6",
            angles.len()
        );
        assert!(angles.len() > 100, "{}", angles.len());
        medians.push(m);
    }
    assert!(medians[0] > 60.0, "the signal's lobe: {}", medians[0]);
    assert!(medians[1] <= 15.0, "CSD: {}", medians[1]);
    assert!(medians[2] <= 15.0, "CSA: {}", medians[2]);
}

/// A response read from a file (MRtrix's format) gives the same fODF as the same
/// response estimated in the run.
#[test]
fn a_response_file_gives_the_estimated_responses_fodf() {
    let inputs = inputs();
    let estimate = estimate_response(&inputs, 8, DEFAULT_RESPONSE_FA).expect("response");
    assert!(estimate.voxels > 50, "{}", estimate.voxels);
    let [l1, l2, _] = estimate.eigenvalues;
    // White matter at b ~ 1000: a prolate tensor of the usual size.
    assert!(
        (1.2e-3..2.0e-3).contains(&l1) && (1e-4..6e-4).contains(&l2),
        "{l1} {l2}"
    );
    let model = odf_model(OdfMethod::Csd, 8, 1.0);
    let (auto, _) = fit_with_response(&inputs, &model, None, &mut |_| {}).expect("auto");
    let dir = fresh_dir("odf-response-file");
    let file = dir.join("wm.txt");
    std::fs::write(&file, estimate.response.to_text()).unwrap();
    let out = dir.join("fod.nii");
    let run = fit_small_64d(
        &[
            "--bvec-convention",
            "voxel",
            "--odf",
            "csd",
            "--csd-algorithm",
            "dipy",
            "--basis",
            "dipy",
            "--order",
            "8",
            "--response",
            text(&file),
        ],
        &out,
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let read = read_nifti(&out);
    let mut worst: f64 = 0.0;
    for (a, b) in read.iter().zip(auto.iter()) {
        worst = worst.max((a - b).abs() / (1.0 + b.abs()));
    }
    // float32 output and the response's decimal text.
    assert!(worst < 1e-5, "{worst}");
}

fn read_nifti(path: &Path) -> ndarray::ArrayD<f64> {
    let object = ReaderOptions::new().read_file(path).expect("reading NIfTI");
    object.into_volume().into_ndarray::<f64>().expect("voxels")
}

fn read_description(path: &Path) -> String {
    let object = ReaderOptions::new().read_file(path).expect("reading NIfTI");
    let bytes = object.header().descrip.clone();
    String::from_utf8_lossy(&bytes)
        .trim_end_matches('\0')
        .to_string()
}

/// `fit --odf` records its model and basis, and `peaks` writes 3 N values per voxel:
/// unit directions times amplitudes, highest first, NaN where missing.
#[test]
fn command_line_writes_odfs_and_peaks() {
    let dir = fresh_dir("odf-cli");
    let inputs = inputs();
    for (method, band) in [("csd", 8), ("csa", 6), ("qball", 4)] {
        let odf = dir.join(format!("{method}.nii.gz"));
        let run = fit_small_64d(
            &[
                "--bvec-convention",
                "voxel",
                "--odf",
                method,
                // --lmax is the name MRtrix and DIPY users know; it is --order's alias.
                if method == "csa" { "--lmax" } else { "--order" },
                &band.to_string(),
                "--quiet",
            ],
            &odf,
        );
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let description = read_description(&odf);
        assert!(
            description.starts_with(&format!(
                "glyphcast fit: SH band {band} tournier07 {method} ODF"
            )),
            "{description}"
        );
        let peaks_file = dir.join(format!("{method}-peaks.nii"));
        let run = glyphcast(&["peaks", text(&odf), "-o", text(&peaks_file), "--count", "2"]);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let coeffs = read_nifti(&odf);
        let peaks = read_nifti(&peaks_file);
        assert_eq!(peaks.shape(), &[10, 10, 10, 6]);
        let finder = PeakFinder::new(
            band,
            ShBasis::Tournier07,
            false,
            PeakOptions {
                count: 2,
                ..PeakOptions::default()
            },
        )
        .unwrap();
        let (mut single, mut double) = (0, 0);
        for x in 0..10 {
            for z in 0..10 {
                let c: Vec<f64> = (0..coeffs.shape()[3])
                    .map(|k| coeffs[[x, 4, z, k]])
                    .collect();
                let expected = finder.find(&c);
                let got: Vec<f64> = (0..6).map(|k| peaks[[x, 4, z, k]]).collect();
                for (i, p) in expected.iter().enumerate() {
                    let v = DVec3::new(got[3 * i], got[3 * i + 1], got[3 * i + 2]);
                    assert!((v.length() - p.value).abs() < 1e-4 * p.value, "{v} {p:?}");
                    assert!(axis_angle(v, p.direction) < 0.01);
                    // The amplitude is the ODF's value in that direction.
                    let at = sh_eval(band, ShBasis::Tournier07, false, &c, v.normalize());
                    assert!((at - v.length()).abs() < 1e-3 * at.abs(), "{at} {v}");
                }
                assert!(got[3 * expected.len()..].iter().all(|v| v.is_nan()));
                match expected.len() {
                    1 => single += 1,
                    2 => double += 1,
                    _ => {}
                }
            }
        }
        eprintln!("{method}: slice y = 4: {single} voxels with one peak, {double} with two");
        assert!(single > 0, "{method}: no voxel with one peak");
    }
    // The DTI frame check of the NIfTI output is done by the library tests; here the
    // inputs were read as the command reads them with --bvec-convention voxel.
    assert_eq!(inputs.dwi.spatial_shape(), [10, 10, 10]);
}

fn write_lines(path: &Path, rows: &[String]) {
    std::fs::write(path, rows.join("\n") + "\n").unwrap();
}

#[test]
fn bad_odf_input_fails_cleanly() {
    let dwi = dipy_data("small_64D.nii");
    let bval = dipy_data("small_64D.bval");
    let bvec = dipy_data("small_64D.bvec");
    let scratch = fresh_dir("odf-bad-inputs");
    // Multi-shell: half the weighted volumes at b = 2000.
    let bvals: Vec<f64> = std::fs::read_to_string(&bval)
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    let shells: Vec<String> = bvals
        .iter()
        .enumerate()
        .map(|(i, b)| {
            if *b > 50.0 && i % 2 == 0 {
                "2000".into()
            } else {
                b.to_string()
            }
        })
        .collect();
    let multi = scratch.join("multi.bval");
    write_lines(&multi, &[shells.join(" ")]);
    let two_rows = scratch.join("two-shells.txt");
    write_lines(&two_rows, &["500 -200 50".into(), "300 -100 20".into()]);
    let short = scratch.join("short.txt");
    write_lines(&short, &["500 -200 50".into()]);
    let base = |out: &Path, bval_file: &Path| -> Vec<String> {
        vec![
            "fit".into(),
            text(&dwi).into(),
            "--bval".into(),
            text(bval_file).into(),
            "--bvec".into(),
            text(&bvec).into(),
            "-o".into(),
            text(out).into(),
        ]
    };
    let cases: Vec<(&str, &Path, Vec<&str>, Vec<&str>)> = vec![
        // 91 coefficients of band 12 from 64 directions (CSD runs: its constraint
        // determines what the directions do not, as dwi2fod -lmax 12 does).
        (
            "too-few",
            &bval,
            vec!["--odf", "csa", "--order", "12"],
            vec!["small_64D.bvec", "64", "91"],
        ),
        (
            "multi-shell",
            &multi,
            vec!["--odf", "csd", "--order", "8"],
            vec!["multi.bval", "single-shell CSD", "multi-shell"],
        ),
        (
            "no-fa",
            &bval,
            vec!["--odf", "csd", "--order", "8", "--response-fa", "0.99"],
            vec!["small_64D.nii", "FA above 0.99", "--response"],
        ),
        (
            "two-row-response",
            &bval,
            vec![
                "--odf",
                "csd",
                "--order",
                "8",
                "--response",
                text(&two_rows),
            ],
            vec!["two-shells.txt", "multi-shell"],
        ),
        // A response of fewer bands than --order runs (its missing bands are zero, as in
        // dwi2fod): tests/fit_conventions.rs.
    ];
    for (case, bval_file, options, words) in cases {
        let out_dir = fresh_dir(&format!("odf-bad-{case}"));
        let mut args = base(&out_dir.join("fod.nii.gz"), bval_file);
        args.extend(options.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let line = expect_failure(&args, &out_dir, &words);
        eprintln!("{case}: {line}");
    }
    // `peaks` on an image that is no SH series: 65 volumes is no (L+1)(L+2)/2.
    let out_dir = fresh_dir("odf-bad-peaks");
    let out = out_dir.join("peaks.nii");
    expect_failure(
        &["peaks", text(&dwi), "-o", text(&out)],
        &out_dir,
        &["small_64D.nii", "65 coefficients"],
    );
    // Flags of CSD with another model, and unknown models, are usage errors (exit 2).
    let out_dir = fresh_dir("odf-bad-usage");
    let out = out_dir.join("odf.nii");
    for extra in [
        vec!["--odf", "csa", "--tau", "0.2"],
        vec!["--odf", "csa", "--response", text(&short)],
        vec!["--odf", "dti"],
    ] {
        let mut args = base(&out, &bval);
        args.extend(["--order".into(), "6".into()]);
        args.extend(extra.iter().map(|s| s.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = glyphcast(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(
            stderr.contains(extra[extra.len() - 2]) || stderr.contains("dti"),
            "{stderr}"
        );
        assert!(std::fs::read_dir(&out_dir).unwrap().next().is_none());
    }
}

/// The fODF of the real DWI renders (validation layer on) as the float64 reference of
/// the same scene draws it: coverage and depth agree, and the CSD glyphs are slimmer
/// than those of the signal's own series (fibre lobes, not blobs).
#[test]
fn fodf_glyphs_render_as_the_reference_draws_them() {
    use glyphcast::accuracy::compare_depth;
    use glyphcast::glyph::reference::reference_depth;
    use glyphcast::render::glyph_data::prepare_scene;
    use glyphcast::scene::Scene;
    let dir = fresh_dir("odf-render");
    let mut coverage = Vec::new();
    for series in ["--odf=csd", "--sh"] {
        let name = series.trim_start_matches("--").replace('=', "-");
        let volume = dir.join(format!("{name}.nii.gz"));
        let run = fit_small_64d(&["--order", "8", "--quiet", series], &volume);
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let (png, depth, scene) = (
            dir.join(format!("{name}.png")),
            dir.join(format!("{name}.npy")),
            dir.join(format!("{name}.json")),
        );
        let run = glyphcast(&[
            "render",
            "--sh",
            text(&volume),
            "--slice",
            "axial",
            "--voxels",
            "2:6,2:6,:",
            "--norm",
            "per-glyph",
            "--negative",
            "hide",
            "--width",
            "160",
            "--height",
            "160",
            "-o",
            text(&png),
            "--depth-out",
            text(&depth),
            "--save-scene",
            text(&scene),
        ]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{stderr}");
        assert!(!stderr.contains("VUID"), "{stderr}");
        let saved = Scene::load(&scene).expect("the saved scene");
        let (shape, rendered) = glyphcast::io::npy::read_npy_f32(&depth).expect("depth map");
        assert_eq!(shape, vec![160, 160]);
        let sets = prepare_scene(&saved, 0.0).expect("preparing");
        let world: Vec<_> = sets.iter().flat_map(|s| s.world.iter().cloned()).collect();
        assert_eq!(world.len(), 16);
        let reference = reference_depth(&world, &saved.camera, 160, 160);
        let scale = world.iter().map(|g| g.scale * g.bound).fold(0.0, f64::max);
        let c = compare_depth(&rendered, &reference, 160, 160, scale);
        eprintln!("{name}: {c}");
        assert!(
            c.holes == 0 && c.false_hits == 0 && c.median_error < 1e-3,
            "{name}: {c}"
        );
        coverage.push(c.covered as f64);
    }
    // Each glyph scaled to the same largest radius: thin fibre lobes cover far fewer
    // pixels than the signal's rounded profiles.
    eprintln!(
        "covered pixels: fODF {}, signal {}",
        coverage[0], coverage[1]
    );
    assert!(coverage[0] < 0.6 * coverage[1], "{coverage:?}");
}

/// `peaks` on a NIfTI file that records no basis (MRtrix's func_coef, legacy
/// tournier07) needs `--basis` (exit 2 without it), and then finds the same peaks as the
/// library in that basis.
#[test]
fn peaks_of_an_unrecorded_basis_need_basis() {
    let dir = fresh_dir("odf-peaks-basis");
    let odf = dipy_data("func_coef.nii.gz");
    let out = dir.join("peaks.nii.gz");
    let run = glyphcast(&["peaks", text(&odf), "-o", text(&out)]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("func_coef.nii.gz") && stderr.contains("--basis"),
        "{stderr}"
    );
    assert!(std::fs::read_dir(&dir).unwrap().next().is_none());
    let run = glyphcast(&[
        "peaks",
        text(&odf),
        "--basis",
        "tournier07",
        "--legacy",
        "-o",
        text(&out),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let coeffs = read_nifti(&odf);
    let peaks = read_nifti(&out);
    assert_eq!(peaks.shape(), &[2, 3, 4, 9]);
    let finder = PeakFinder::new(8, ShBasis::Tournier07, true, PeakOptions::default()).unwrap();
    let c: Vec<f64> = (0..45).map(|k| coeffs[[1, 2, 3, k]]).collect();
    let expected = finder.find(&c);
    assert!(!expected.is_empty());
    let v = DVec3::new(
        peaks[[1, 2, 3, 0]],
        peaks[[1, 2, 3, 1]],
        peaks[[1, 2, 3, 2]],
    );
    assert!(axis_angle(v, expected[0].direction) < 0.01);
    assert!((v.length() - expected[0].value).abs() < 1e-4 * expected[0].value);
}
