//! Fibre ODFs as MRtrix users run them (issue 26.3 to 26.5): an lmax-12 CSD from a
//! response of bands up to 8 (as `dwi2fod -lmax 12` runs it); the automatic response on
//! a head with background chooses tissue only and says which voxels; the peaks of a
//! band-0 (isotropic) image are none.
use crate::common;
use common::{dipy_data, fit_small_64d, fresh_dir, glyphcast, text};
use glam::{DMat4, DVec3};
use glyphcast::rng::SplitMix64;
use glyphcast::scene::ShBasis;
use glyphcast_dmri::fit::peaks::{PeakFinder, PeakOptions};
use glyphcast_dmri::fit::response::{DEFAULT_RESPONSE_FA, estimate_response};
use glyphcast_dmri::fit::{FitFiles, FitInputs};
use glyphcast_dmri::io::image::read_image;
use ndarray::{ArrayD, IxDyn};
use std::path::{Path, PathBuf};

fn small_64d(dwi: PathBuf) -> FitInputs {
    FitInputs::load(FitFiles {
        dwi,
        bval: Some(dipy_data("small_64D.bval")),
        bvec: Some(dipy_data("small_64D.bvec")),
        mask: None,
    })
    .expect("loading the DWI")
}

/// small_64D (10^3 voxels of brain) in the middle of a 24^3 volume of air: Rician noise
/// of sigma 10 in every volume (S0 about 12, against a brain median of about 300),
/// whose DTI fits have high FA as often as not.
fn head_with_background(dir: &Path) -> PathBuf {
    let brain = small_64d(dipy_data("small_64D.nii"));
    let volumes = brain.dwi.volume_count();
    let mut rng = SplitMix64::new(26);
    // |N(0, 10) + i N(0, 10)| by Box-Muller: a Rayleigh distribution of scale 10.
    let mut data = ArrayD::from_shape_fn(IxDyn(&[24, 24, 24, volumes]), |_| {
        let (u, v): (f64, f64) = (1.0 - rng.unit(), rng.unit());
        let radius = (-2.0 * u.ln()).sqrt() * 10.0;
        let (a, b) = (
            radius * (std::f64::consts::TAU * v).cos(),
            radius * (std::f64::consts::TAU * v).sin(),
        );
        (a * a + b * b).sqrt()
    });
    for ((x, y, z, v), value) in brain.dwi.signal.indexed_iter() {
        data[[x + 7, y + 7, z + 7, v]] = *value;
    }
    let path = dir.join("head.nii");
    common::write_nifti(&path, &data, DMat4::IDENTITY);
    path
}

/// The automatic response on a head with background is the response of the brain
/// alone: the same voxels (every brain voxel lies inside the central cube), and the
/// command line says which (count, S0 range, where).
#[test]
fn automatic_response_chooses_tissue_and_says_which() {
    let dir = fresh_dir("fit-response-background");
    let head = head_with_background(&dir);
    let brain = estimate_response(
        &small_64d(dipy_data("small_64D.nii")),
        8,
        DEFAULT_RESPONSE_FA,
    )
    .expect("brain response");
    let estimate =
        estimate_response(&small_64d(head.clone()), 8, DEFAULT_RESPONSE_FA).expect("response");
    let threshold = estimate.threshold.expect("a background threshold");
    eprintln!(
        "threshold {threshold:.1}, {} tissue voxels, {} chosen, S0 {:?}, bounds {:?}",
        estimate.tissue_voxels, estimate.voxels, estimate.s0_range, estimate.bounds
    );
    assert!(
        threshold > 40.0 && threshold < estimate.s0_range.0,
        "{threshold}"
    );
    assert_eq!(estimate.voxels, brain.voxels);
    assert_eq!(estimate.s0_range, brain.s0_range);
    for (a, b) in estimate.response.zonal.iter().zip(&brain.response.zonal) {
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{a} vs {b}");
    }
    for (axis, bound) in estimate.bounds.iter().enumerate() {
        assert!(bound[0] >= 7 && bound[1] <= 16, "axis {axis}: {bound:?}");
    }
    // Without the tissue mask the air would have counted: many of its noise tensors
    // have FA above the threshold.
    let inputs = small_64d(head.clone());
    let dti = glyphcast_dmri::fit::fit(
        &inputs,
        &glyphcast_dmri::fit::FitModel::Tensor { order: 2 },
        &mut |_| {},
    )
    .unwrap();
    let noisy_air = (2..23)
        .flat_map(|x| (2..23).flat_map(move |y| (2..23).map(move |z| [x, y, z])))
        .filter(|v| v.iter().any(|&i| !(7..17).contains(&i)))
        .filter(|&[x, y, z]| {
            let c: Vec<f64> = (0..6).map(|k| dti[[x, y, z, k]]).collect();
            glyphcast_dmri::fit::dti::DiffusionTensor::from_coefficients(&c).is_some_and(|t| {
                t.eigenvalues[2] > 0.0 && t.fractional_anisotropy() > DEFAULT_RESPONSE_FA
            })
        })
        .count();
    assert!(noisy_air > 100, "{noisy_air} air voxels with high FA");
    // The brain alone has no background: no threshold, every voxel with S0 > 0 counts.
    assert_eq!(brain.threshold, None);
    let out = glyphcast(&[
        "fit",
        text(&head),
        "--bval",
        text(&dipy_data("small_64D.bval")),
        "--bvec",
        text(&dipy_data("small_64D.bvec")),
        "--odf",
        "csd",
        "--order",
        "6",
        "-o",
        text(&dir.join("fod.nii")),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("response: "))
        .unwrap_or_else(|| panic!("no response line: {stderr}"));
    let expected = format!("response: {} voxels with FA > 0.7", brain.voxels);
    assert!(line.starts_with(&expected), "{line}");
    assert!(
        line.contains("Otsu") && line.contains(" i 7..") && line.contains("S0 "),
        "{line}"
    );
}

/// `fit --odf csd --order 12` with a response of bands up to 8 runs, as `dwi2fod -lmax
/// 12` does: 91 coefficients, bands 10 and 12 set by the constraint; its first peaks stay
/// within a few degrees of the lmax-8 fit's where one fibre dominates (FA > 0.6).
#[test]
fn csd_order_12_from_an_order_8_response() {
    let dir = fresh_dir("fit-csd-lmax12");
    let response = dir.join("wm.txt");
    let inputs = small_64d(dipy_data("small_64D.nii"));
    let estimate = estimate_response(&inputs, 8, DEFAULT_RESPONSE_FA).expect("response");
    std::fs::write(&response, estimate.response.to_text()).expect("response file");
    let run = |order: &str, out: &Path| {
        let args = [
            "--odf",
            "csd",
            "--order",
            order,
            "--response",
            text(&response),
        ];
        let done = fit_small_64d(&args, out);
        let stderr = String::from_utf8_lossy(&done.stderr).into_owned();
        assert!(done.status.success(), "{stderr}");
        stderr
    };
    let (low, high) = (dir.join("fod8.nii"), dir.join("fod12.nii"));
    run("8", &low);
    let stderr = run("12", &high);
    assert!(stderr.contains("bands 10 to 12"), "{stderr}");
    let (a, b) = (read_image(&low).unwrap(), read_image(&high).unwrap());
    assert_eq!(b.data.shape(), &[10, 10, 10, 91]);
    assert!(b.data.iter().all(|v| v.is_finite()));
    let finder =
        |band| PeakFinder::new(band, ShBasis::Tournier07, false, PeakOptions::default()).unwrap();
    let (f8, f12) = (finder(8), finder(12));
    let dti = glyphcast_dmri::fit::fit(
        &inputs,
        &glyphcast_dmri::fit::FitModel::Tensor { order: 2 },
        &mut |_| {},
    )
    .unwrap();
    let mut angles = Vec::new();
    for ((x, y, z), _) in dti.index_axis(ndarray::Axis(3), 0).indexed_iter() {
        let c: Vec<f64> = (0..6).map(|k| dti[[x, y, z, k]]).collect();
        let fa = glyphcast_dmri::fit::dti::DiffusionTensor::from_coefficients(&c)
            .map_or(0.0, |t| t.fractional_anisotropy());
        if fa <= 0.6 {
            continue;
        }
        let lane = |image: &glyphcast_dmri::io::image::Image, n| -> Vec<f64> {
            (0..n).map(|k| image.data[[x, y, z, k]]).collect()
        };
        let (p8, p12) = (f8.find(&lane(&a, 45)), f12.find(&lane(&b, 91)));
        let (Some(p8), Some(p12)) = (p8.first(), p12.first()) else {
            panic!("voxel {x},{y},{z}: no peak");
        };
        let d: DVec3 = p8.direction;
        angles.push(d.dot(p12.direction).abs().min(1.0).acos().to_degrees());
    }
    angles.sort_by(f64::total_cmp);
    let median = angles[angles.len() / 2];
    eprintln!(
        "{} voxels, median {median:.2} degrees, max {:.2}",
        angles.len(),
        angles[angles.len() - 1]
    );
    assert!(angles.len() > 20 && median < 3.0, "{angles:?}");
}

/// The peaks of a band-0 image (an isotropic tissue ODF) are none: NaN in every voxel,
/// with a note; a band-2 image of the same values plus one anisotropic voxel has one.
#[test]
fn band_0_images_have_no_peaks() {
    let dir = fresh_dir("peaks-band-0");
    let iso = ArrayD::from_shape_fn(IxDyn(&[3, 2, 2, 1]), |i| 1.0 + i[0] as f64);
    let path = dir.join("gm.nii");
    common::write_nifti(&path, &iso, DMat4::IDENTITY);
    let out_path = dir.join("peaks.nii");
    let out = glyphcast(&[
        "peaks",
        text(&path),
        "--basis",
        "mrtrix",
        "-o",
        text(&out_path),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("note: ") && stderr.contains("no peak"),
        "{stderr}"
    );
    let peaks = read_image(&out_path).unwrap();
    assert!(peaks.data.iter().all(|v| v.is_nan()), "{:?}", peaks.data);
    // Band 2 with only band 0 set is isotropic too; a z-fibre term gives one peak.
    let finder = PeakFinder::new(2, ShBasis::Tournier07, false, PeakOptions::default()).unwrap();
    assert!(finder.find(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]).is_empty());
    let peaks = finder.find(&[1.0, 0.0, 0.0, 0.5, 0.0, 0.0]);
    assert_eq!(peaks.len(), 1);
    assert!(peaks[0].direction.z.abs() > 0.999, "{peaks:?}");
}
