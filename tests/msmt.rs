//! Multi-shell multi-tissue CSD (`fit --odf msmt`) on tests/data/msmt, a 5x5x3 DWI of
//! known WM/GM/CSF mixtures at b = 0, 1000, 2000, 3000 made by `tools/msmt_fixtures.py`,
//! which also ran DIPY's `MultiShellDeconvModel` (and MRtrix's `dwi2fod msmt_csd`) on it
//! with the responses in wm.txt, gm.txt, csf.txt (CI runs neither).
//!
//! - With DIPY's constraint directions, glyphcast's QP gives DIPY's problem's solution
//!   (solved tightly by the script) coefficient for coefficient.
//! - The command line, with its own constraint directions, gives DIPY's tissue fractions
//!   and peaks; on the voxels whose WM is a band-8 fODF the known mixture comes back.
//! - Estimated responses come near the true ones; bad input fails cleanly.
use crate::common;

use common::{
    DwiFiles, axis_angle, expect_failure, fresh_dir, glyphcast, numbers, test_data, text,
};
use glam::DVec3;
use glyphcast::scene::ShBasis;
use glyphcast_dmri::fit::msmt::{MsmtFitter, MsmtProblem, Shells, TissueResponses};
use glyphcast_dmri::fit::peaks::{PeakFinder, PeakOptions};
use glyphcast_dmri::fit::response_msmt::{estimate_responses, read_responses};
use nifti::{IntoNdArray, NiftiObject, ReaderOptions};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// DIPY's default basis: descoteaux07, legacy.
const DIPY_BASIS: (ShBasis, bool) = (ShBasis::Descoteaux07, true);

fn data(name: &str) -> PathBuf {
    test_data("msmt", name)
}

fn fixture() -> Value {
    let text = std::fs::read_to_string(data("msmt-dipy.json")).expect("reading the fixture");
    serde_json::from_str(&text).expect("parsing the fixture")
}

fn vector(v: &Value) -> DVec3 {
    let n = numbers(v);
    DVec3::new(n[0], n[1], n[2])
}

/// The responses the fixture's DWI was made with (wm.txt, gm.txt, csf.txt).
fn true_responses(shells: &Shells) -> TissueResponses {
    read_responses(&data("wm.txt"), &data("gm.txt"), &data("csf.txt"), shells)
        .expect("reading the responses")
}

/// `--odf msmt` with the three response files.
fn msmt_with<'a>(wm: &'a Path, gm: &'a Path, csf: &'a Path) -> [&'a str; 8] {
    [
        "--odf",
        "msmt",
        "--response",
        text(wm),
        "--response-gm",
        text(gm),
        "--response-csf",
        text(csf),
    ]
}

fn voxel(record: &Value) -> [usize; 3] {
    let v = numbers(&record["voxel"]);
    [v[0] as usize, v[1] as usize, v[2] as usize]
}

#[test]
fn qp_with_dipys_constraint_directions_is_dipys_solution() {
    let fixture = fixture();
    // DIPY reads the b-vectors as stored: the voxel axes (the fixture's affine has a
    // negative determinant, so FSL's convention agrees).
    let inputs = DwiFiles::msmt().inputs();
    let shells = Shells::group(&inputs.gradients.bvals);
    assert_eq!(shells.len(), 4, "{shells:?}");
    let responses = true_responses(&shells);
    let constraint: Vec<DVec3> = fixture["constraint_directions"]
        .as_array()
        .unwrap()
        .iter()
        .map(vector)
        .collect();
    let problem = MsmtProblem {
        band: 8,
        basis: DIPY_BASIS,
        gradients: &inputs.gradients,
        shells: &shells,
        responses: &responses,
    };
    let fitter = MsmtFitter::with_constraint(&problem, &constraint).unwrap();
    let mut solver = fitter.solver().unwrap();
    let (mut worst_tight, mut worst_dipy) = (0.0f64, 0.0f64);
    for record in fixture["voxels"].as_array().unwrap() {
        let [x, y, z] = voxel(record);
        let series: Vec<f64> = inputs.dwi.signal.slice(ndarray::s![x, y, z, ..]).to_vec();
        let odfs = fitter.fit(&mut solver, &series).expect("solved");
        // DIPY's order: CSF, GM, then the WM series.
        let mine: Vec<f64> = [odfs.csf, odfs.gm].into_iter().chain(odfs.wm).collect();
        let scale = numbers(&record["tight_csf_gm_wm"])
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        for (key, worst) in [
            ("tight_csf_gm_wm", &mut worst_tight),
            ("dipy_csf_gm_wm", &mut worst_dipy),
        ] {
            let theirs = numbers(&record[key]);
            let gap = mine
                .iter()
                .zip(&theirs)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            *worst = worst.max(gap / scale);
        }
    }
    eprintln!(
        "largest gap to the tight solve {worst_tight:.2e}, to DIPY's OSQP run {worst_dipy:.2e} (of the voxel's largest coefficient)"
    );
    // Both solve the same QP tightly; the interior points stop a little inside the
    // many nearly active constraints (as in the unit test of `msmt`).
    assert!(worst_tight < 5e-4, "{worst_tight}");
    // DIPY's own call leaves the choice of solver to cvxpy, which takes OSQP with its
    // default tolerances (1e-3 relative): up to a tenth of the largest coefficient off.
    assert!(worst_dipy < 0.15, "{worst_dipy}");
}

/// `fit --odf msmt` with the three response files into `dir`: the WM, GM and CSF volumes.
fn run_cli(dir: &Path) -> [ndarray::ArrayD<f64>; 3] {
    let wm = dir.join("wm.nii.gz");
    let (wm_response, gm, csf) = (data("wm.txt"), data("gm.txt"), data("csf.txt"));
    let mut model = vec!["--order", "8", "--basis", "dipy"];
    model.extend(msmt_with(&wm_response, &gm, &csf));
    let run = glyphcast(&DwiFiles::msmt().fit_args(&model, &wm));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("shells b = 0, 1000, 2000, 3001"),
        "{stderr}"
    );
    let read = |name: &str| {
        let object = ReaderOptions::new()
            .read_file(dir.join(name))
            .expect("reading an output");
        let description = String::from_utf8_lossy(&object.header().descrip).to_string();
        let tissue = name
            .trim_end_matches(".nii.gz")
            .trim_start_matches("wm_")
            .to_ascii_uppercase();
        assert!(
            description.contains("descoteaux07 legacy msmt"),
            "{name}: {description}"
        );
        assert!(
            name == "wm.nii.gz" || description.contains(&tissue),
            "{description}"
        );
        object.into_volume().into_ndarray::<f64>().expect("voxels")
    };
    [
        read("wm.nii.gz"),
        read("wm_gm.nii.gz"),
        read("wm_csf.nii.gz"),
    ]
}

#[test]
fn command_line_matches_dipy_and_the_known_mixture() {
    let fixture = fixture();
    let dir = fresh_dir("msmt-cli");
    let [wm, gm, csf] = run_cli(&dir);
    assert_eq!(wm.shape(), &[5, 5, 3, 45]);
    assert_eq!(gm.shape()[..3], [5, 5, 3]);
    let finder = PeakFinder::new(8, DIPY_BASIS.0, DIPY_BASIS.1, PeakOptions::default()).unwrap();
    let sqrt_4pi = (4.0 * std::f64::consts::PI).sqrt();
    let (mut fraction_gap, mut peak_gap, mut truth_gap, mut truth_peak) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut peaks_compared = 0;
    for record in fixture["voxels"].as_array().unwrap() {
        let [x, y, z] = voxel(record);
        let coeffs: Vec<f64> = (0..45).map(|k| wm[[x, y, z, k]]).collect();
        let fractions = [
            csf[[x, y, z, 0]] * sqrt_4pi,
            gm[[x, y, z, 0]] * sqrt_4pi,
            coeffs[0] * sqrt_4pi,
        ];
        let dipy = numbers(&record["dipy_fractions_csf_gm_wm"]);
        for (a, b) in fractions.iter().zip(&dipy) {
            fraction_gap = fraction_gap.max((a - b).abs());
        }
        let peaks = finder.find(&coeffs);
        let dipy_peaks: Vec<DVec3> = record["dipy_peak_directions"]
            .as_array()
            .unwrap()
            .iter()
            .map(vector)
            .collect();
        let wm_share = dipy[2];
        // DIPY's peaks are vertices of its sphere (about 1 degree apart), unrefined; on
        // the broad lobes of the band-8 crossings they wander by several degrees, and
        // those voxels are compared with their known fODF's peaks below instead.
        let tensor = record["wm_model"] == "tensor";
        if tensor && wm_share > 0.25 && peaks.len() == dipy_peaks.len() {
            for d in &dipy_peaks {
                let nearest = peaks
                    .iter()
                    .map(|p| axis_angle(p.direction, *d))
                    .fold(180.0, f64::min);
                peak_gap = peak_gap.max(nearest);
                peaks_compared += 1;
            }
        }
        // Band-8 fODF voxels: the model holds exactly, the mixture comes back.
        if let Some(truth) = record.get("true_csf_gm_wm") {
            let truth = numbers(truth);
            let known = [
                record["csf"].as_f64().unwrap(),
                record["gm"].as_f64().unwrap(),
                record["wm"].as_f64().unwrap(),
            ];
            for (a, b) in fractions.iter().zip(known) {
                truth_gap = truth_gap.max((a - b).abs());
            }
            let true_peaks = finder.find(&truth[2..]);
            for p in &true_peaks {
                let nearest = peaks
                    .iter()
                    .map(|q| axis_angle(q.direction, p.direction))
                    .fold(180.0, f64::min);
                truth_peak = truth_peak.max(nearest);
            }
        }
        // Single-fibre tensor voxels without noise: the fibre is the first peak.
        let fibres = record["fibres"].as_array().unwrap();
        if fibres.len() == 1
            && !record["noisy"].as_bool().unwrap()
            && record["wm"].as_f64().unwrap() >= 0.3
        {
            let fibre = vector(&fibres[0]);
            assert!(
                axis_angle(peaks[0].direction, fibre) < 1.0,
                "{record}: {peaks:?}"
            );
        }
    }
    eprintln!(
        "fractions within {fraction_gap:.4} of DIPY's, {peaks_compared} peaks within {peak_gap:.2} degrees; \
         band-8 voxels: fractions within {truth_gap:.2e} of the mixture, peaks within {truth_peak:.3} degrees"
    );
    assert!(fraction_gap < 0.01, "{fraction_gap}");
    // The noisy crossings differ most (2.5 degrees): glyphcast constrains 321
    // directions, DIPY 362.
    assert!(
        peaks_compared >= 40 && peak_gap < 3.0,
        "{peaks_compared} {peak_gap}"
    );
    assert!(truth_gap < 1e-3, "{truth_gap}");
    assert!(truth_peak < 0.5, "{truth_peak}");
}

#[test]
fn estimated_responses_come_near_the_true_ones() {
    let inputs = DwiFiles::msmt().inputs();
    let shells = Shells::group(&inputs.gradients.bvals);
    let truth = true_responses(&shells);
    let estimate = estimate_responses(&inputs, &shells, 8, 0.7).expect("estimating");
    // Single-fibre and nearly single-fibre voxels are WM, the pure GM and CSF voxels
    // (one in each slice) and GM-rich mixtures are GM and CSF.
    assert!(
        estimate.voxels.iter().all(|&n| n >= 3),
        "{:?}",
        estimate.voxels
    );
    for (shell, (mine, theirs)) in estimate.responses.wm.iter().zip(&truth.wm).enumerate() {
        // Bands 0 and 2 within 6 % of band 0 at b = 0 to 2000, 12 % at 3000: the WM
        // class holds the band-8 voxels, broader than a tensor, and a DTI fit per shell
        // flattens the b = 3000 profile.
        let tolerance = if shell == 3 { 0.12 } else { 0.06 };
        for l in 0..2.min(mine.len()) {
            let gap = (mine[l] - theirs[l]).abs() / theirs[0];
            assert!(
                gap < tolerance,
                "shell {shell}, l = {}: {mine:?} vs {theirs:?}",
                2 * l
            );
        }
    }
    for (mine, theirs) in estimate.responses.gm.iter().zip(&truth.gm) {
        assert!(
            (mine - theirs).abs() < 0.06 * truth.gm[0],
            "{:?} vs {:?}",
            estimate.responses.gm,
            truth.gm
        );
    }
    // CSF at b = 0 and 1000; past that its signal is in the noise of the noisy voxel.
    for (mine, theirs) in estimate.responses.csf.iter().zip(&truth.csf).take(2) {
        assert!(
            (mine - theirs).abs() < 0.06 * truth.csf[0],
            "{:?} vs {:?}",
            estimate.responses.csf,
            truth.csf
        );
    }
}

#[test]
fn bad_input_is_refused_naming_the_file() {
    let dir = fresh_dir("msmt-bad");
    let out = dir.join("wm.nii.gz");
    let (wm, gm, csf) = (data("wm.txt"), data("gm.txt"), data("csf.txt"));
    let write = |name: &str, rows: &str| {
        let path = dir.join("..").join(name);
        std::fs::write(&path, rows).unwrap();
        path
    };
    // A single-shell response where every shell needs a row.
    let single = write("msmt-single.txt", "# Shells: 1000\n1781.5 -633.5 107.7\n");
    // Rows for other shells than the data's.
    let shifted = write(
        "msmt-shifted.txt",
        "# Shells: 0,1000,2500,3000\n3000\n2000\n900\n400\n",
    );
    // A GM response with an anisotropic column.
    let anisotropic = write("msmt-aniso.txt", "3000 0\n2000 -10\n900 0\n400 0\n");
    // (DWI, model options, the words the error holds: the file and the field or row).
    let (msmt, small) = (DwiFiles::msmt(), DwiFiles::small_64d());
    let cases: [(&DwiFiles, &[&str], &[&str]); 5] = [
        // Single-shell CSD on this multi-shell DWI points to msmt.
        (
            &msmt,
            &["--odf", "csd"],
            &["dwi.bval", "multi-shell", "--odf msmt"],
        ),
        (
            &msmt,
            &msmt_with(&single, &gm, &csf),
            &["msmt-single.txt", "rows", "1 row", "4 shells"],
        ),
        (
            &msmt,
            &msmt_with(&wm, &shifted, &csf),
            &["msmt-shifted.txt", "row 3", "b = 2500", "2000"],
        ),
        (
            &msmt,
            &msmt_with(&wm, &anisotropic, &csf),
            &["msmt-aniso.txt", "row 2", "isotropic"],
        ),
        // Single-shell data with msmt: a clear message that names the b-values.
        (
            &small,
            &["--odf", "msmt"],
            &["small_64D.bval", "two non-zero shells", "--odf csd"],
        ),
    ];
    for (dwi, model, words) in cases {
        let mut args = vec!["--order", "8"];
        args.extend_from_slice(model);
        expect_failure(&dwi.fit_args(&args, &out), &dir, words);
    }
    // Flags of another model: usage errors (exit 2).
    for model in [
        ["--odf", "msmt", "--tau", "0.2"],
        ["--odf", "csd", "--gm", "x.nii"],
    ] {
        let mut args = vec!["--order", "8"];
        args.extend_from_slice(&model);
        let usage = glyphcast(&msmt.fit_args(&args, &out));
        assert_eq!(
            usage.status.code(),
            Some(2),
            "{model:?}: {}",
            String::from_utf8_lossy(&usage.stderr)
        );
    }
}
