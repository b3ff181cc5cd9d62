//! Real data from DIPY (tests/data/dipy, BSD-3): MRtrix `dwi2SH` coefficients of band 8
//! in the legacy tournier07 basis (func_coef) and the same functions sampled on 81
//! directions (func_discrete, sphere_grad.txt). The SH evaluation must reproduce the
//! samples in that basis, and must not in the other three, so the test tells the bases
//! (and the Condon-Shortley phase) apart.
use std::path::PathBuf;

use glam::DVec3;
use glyphcast::glyph::sh::{ShFitter, sh_count, sh_eval, sh_orders};
use glyphcast::scene::ShBasis;
use ndarray::{ArrayD, IxDyn};
use nifti::{IntoNdArray, NiftiObject, ReaderOptions};

const BAND: u32 = 8;
/// The files store float32 samples up to about 5.7; measured agreement is 2.2e-5, the
/// bound leaves room for other float32 writers of the same data (notes report 2e-4).
const TOLERANCE: f64 = 5e-4;

fn data_path(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/data/dipy")
        .join(name)
}

/// The volume as float64, shape [x, y, z, t] (the nifti crate gives Fortran order).
fn read_volume(name: &str) -> ArrayD<f64> {
    let object = ReaderOptions::new()
        .read_file(data_path(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    object
        .into_volume()
        .into_ndarray::<f64>()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Rows `x y z b` of sphere_grad.txt, without row 0 (the b = 0 entry).
fn read_directions() -> Vec<DVec3> {
    let path = data_path("sphere_grad.txt");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            line.split_whitespace()
                .map(|v| v.parse().unwrap_or_else(|e| panic!("{line}: {e}")))
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), 82);
    assert_eq!(rows[0], vec![0.0; 4], "row 0 is the b = 0 entry");
    rows[1..]
        .iter()
        .map(|r| {
            assert_eq!(r.len(), 4);
            assert_eq!(r[3], 1.0);
            let u = DVec3::new(r[0], r[1], r[2]);
            assert!((u.length() - 1.0).abs() < 1e-4, "{u}");
            u
        })
        .collect()
}

struct Voxel {
    coeffs: Vec<f64>,
    /// Samples at the 81 directions (func_discrete volumes 1..=81).
    samples: Vec<f64>,
}

fn read_voxels() -> Vec<Voxel> {
    let coef = read_volume("func_coef.nii.gz");
    let discrete = read_volume("func_discrete.nii.gz");
    assert_eq!(coef.shape(), &[2, 3, 4, 45]);
    assert_eq!(discrete.shape(), &[2, 3, 4, 82]);
    let mut voxels = Vec::new();
    for x in 0..2 {
        for y in 0..3 {
            for z in 0..4 {
                let at = |a: &ArrayD<f64>, t: usize| a[IxDyn(&[x, y, z, t])];
                voxels.push(Voxel {
                    coeffs: (0..sh_count(BAND)).map(|t| at(&coef, t)).collect(),
                    samples: (1..82).map(|t| at(&discrete, t)).collect(),
                });
            }
        }
    }
    voxels
}

/// Largest |series - sample| over every voxel and direction, in the given basis.
fn max_error(voxels: &[Voxel], dirs: &[DVec3], basis: ShBasis, legacy: bool) -> f64 {
    let mut worst: f64 = 0.0;
    for voxel in voxels {
        for (u, sample) in dirs.iter().zip(&voxel.samples) {
            let value = sh_eval(BAND, basis, legacy, &voxel.coeffs, *u);
            worst = worst.max((value - sample).abs());
        }
    }
    worst
}

#[test]
fn legacy_tournier07_reproduces_func_discrete_and_other_bases_do_not() {
    let voxels = read_voxels();
    let dirs = read_directions();
    let scale = voxels
        .iter()
        .flat_map(|v| v.samples.iter())
        .fold(0.0f64, |m, s| m.max(s.abs()));
    assert!(scale > 0.1, "the samples are not all (near) zero: {scale}");
    let legacy_tournier = max_error(&voxels, &dirs, ShBasis::Tournier07, true);
    println!("legacy tournier07: max error {legacy_tournier:.2e} (samples up to {scale:.2e})");
    assert!(legacy_tournier < TOLERANCE, "{legacy_tournier:.3e}");
    for (basis, legacy) in [
        (ShBasis::Tournier07, false),
        (ShBasis::Descoteaux07, false),
        (ShBasis::Descoteaux07, true),
    ] {
        let error = max_error(&voxels, &dirs, basis, legacy);
        println!("{basis:?} legacy={legacy}: max error {error:.2e}");
        assert!(
            error > 100.0 * TOLERANCE,
            "{basis:?} legacy={legacy} must not match the data: {error:.3e}"
        );
    }
    // Without the Condon-Shortley phase every odd-m function changes sign, which is the
    // same as negating those coefficients.
    let without_phase: Vec<Voxel> = voxels
        .iter()
        .map(|v| Voxel {
            coeffs: sh_orders(BAND)
                .zip(&v.coeffs)
                .map(|((_, m), c)| if m % 2 == 0 { *c } else { -c })
                .collect(),
            samples: v.samples.clone(),
        })
        .collect();
    let error = max_error(&without_phase, &dirs, ShBasis::Tournier07, true);
    println!("legacy tournier07 without Condon-Shortley phase: max error {error:.2e}");
    assert!(error > 100.0 * TOLERANCE, "{error:.3e}");
}

#[test]
fn fitting_func_discrete_recovers_func_coef() {
    let voxels = read_voxels();
    let dirs = read_directions();
    let fitter = ShFitter::new(BAND, ShBasis::Tournier07, true, &dirs, 0.0)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut worst: f64 = 0.0;
    for voxel in &voxels {
        let fitted = fitter
            .try_fit(&voxel.samples)
            .unwrap_or_else(|e| panic!("{e}"));
        for (a, b) in fitted.iter().zip(&voxel.coeffs) {
            worst = worst.max((a - b).abs());
        }
    }
    println!("refit of func_discrete: max coefficient error {worst:.2e}");
    // Measured 6.8e-7: float32 rounding of the samples through the pseudo-inverse of 81
    // directions for 45 coefficients.
    assert!(worst < 1e-5, "{worst:.3e}");
}
