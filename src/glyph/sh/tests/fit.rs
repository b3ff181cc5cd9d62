//! ShFitter against known coefficients and against a direct solve of Descoteaux's
//! normal equations (B^T B + lambda L) w = B^T s.
use glam::DVec3;
use nalgebra::{DMatrix, DVector};

use super::{ALL_BASES, Rng};
use crate::Error;
use crate::glyph::sh::ShBasis;
use crate::glyph::sh::rotate::fibonacci_sphere;
use crate::glyph::sh::{ShFitter, sh_basis_values, sh_count, sh_orders};

fn fitter(band: u32, basis: ShBasis, legacy: bool, dirs: &[DVec3], lambda: f64) -> ShFitter {
    match ShFitter::new(band, basis, legacy, dirs, lambda) {
        Ok(f) => f,
        Err(e) => panic!("{e}"),
    }
}

fn random_directions(rng: &mut Rng, n: usize) -> Vec<DVec3> {
    (0..n).map(|_| rng.direction()).collect()
}

#[test]
fn noiseless_samples_give_back_the_coefficients() {
    let mut rng = Rng::new(30);
    for (basis, legacy) in ALL_BASES {
        let dirs = random_directions(&mut rng, 64);
        let f = fitter(8, basis, legacy, &dirs, 0.0);
        let w = rng.coefficients(sh_count(8));
        let samples = f.fitted_values(&w);
        let fitted = f.fit(&samples);
        w.iter()
            .zip(&fitted)
            .for_each(|(a, b)| assert!((a - b).abs() < 1e-9, "{basis:?} {legacy}: {a} vs {b}"));
    }
}

/// w from (B^T B + lambda L) w = B^T s by LU, the textbook form of Eq. 8.
fn direct_solve(band: u32, dirs: &[DVec3], samples: &[f64], lambda: f64) -> Vec<f64> {
    let rows: Vec<f64> = dirs
        .iter()
        .flat_map(|u| sh_basis_values(band, ShBasis::Descoteaux07, false, *u))
        .collect();
    let b = DMatrix::from_row_slice(dirs.len(), sh_count(band), &rows);
    let laplace = DMatrix::from_diagonal(&DVector::from_iterator(
        sh_count(band),
        sh_orders(band).map(|(l, _)| f64::from(l * l * (l + 1) * (l + 1))),
    ));
    let normal = b.transpose() * &b + laplace * lambda;
    let rhs = b.transpose() * DVector::from_column_slice(samples);
    match normal.lu().solve(&rhs) {
        Some(w) => w.iter().copied().collect(),
        None => panic!("normal equations are singular"),
    }
}

fn band_energy(w: &[f64], band: u32, l_wanted: u32) -> f64 {
    sh_orders(band)
        .zip(w)
        .filter(|((l, _), _)| *l == l_wanted)
        .map(|(_, c)| c * c)
        .sum()
}

#[test]
fn regularisation_matches_a_direct_solve_and_damps_high_bands() {
    let mut rng = Rng::new(31);
    let dirs = random_directions(&mut rng, 81);
    let samples: Vec<f64> = dirs.iter().map(|_| 1.0 + 0.3 * rng.signed()).collect();
    let lambda = 0.006;
    let plain = fitter(8, ShBasis::Descoteaux07, false, &dirs, 0.0).fit(&samples);
    let regular = fitter(8, ShBasis::Descoteaux07, false, &dirs, lambda).fit(&samples);
    let direct = direct_solve(8, &dirs, &samples, lambda);
    regular
        .iter()
        .zip(&direct)
        .for_each(|(a, b)| assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{a} vs {b}"));
    let direct_plain = direct_solve(8, &dirs, &samples, 0.0);
    plain
        .iter()
        .zip(&direct_plain)
        .for_each(|(a, b)| assert!((a - b).abs() < 1e-7 * (1.0 + b.abs()), "{a} vs {b}"));
    for l in [6, 8] {
        let (e_plain, e_regular) = (band_energy(&plain, 8, l), band_energy(&regular, 8, l));
        assert!(
            e_regular < 0.5 * e_plain,
            "band {l}: energy {e_regular:.3e} with lambda vs {e_plain:.3e} without"
        );
    }
    // The mean (l = 0) is not penalised: noise of +-0.3 around 1 keeps it near 2 sqrt(pi).
    let mean = regular[0] / (2.0 * std::f64::consts::PI.sqrt());
    assert!((mean - 1.0).abs() < 0.1, "mean {mean}");
}

#[test]
fn fitter_rejects_bad_input() {
    let mut rng = Rng::new(32);
    let dirs = random_directions(&mut rng, 30);
    let invalid =
        |r: crate::Result<ShFitter>| matches!(r, Err(Error::Data { .. } | Error::Setting { .. }));
    let new =
        |dirs: &[DVec3], lambda: f64| ShFitter::new(8, ShBasis::Tournier07, false, dirs, lambda);
    assert!(
        invalid(new(&dirs, 0.0)),
        "30 directions cannot fit 45 coefficients"
    );
    let mut dirs64 = random_directions(&mut rng, 64);
    assert!(invalid(new(&dirs64, -1.0)));
    assert!(invalid(new(&dirs64, f64::NAN)));
    dirs64[5] = DVec3::ZERO;
    assert!(invalid(new(&dirs64, 0.0)));
    let equator: Vec<DVec3> = (0..100)
        .map(|i| {
            let a = i as f64 * 0.1;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    assert!(
        invalid(new(&equator, 0.0)),
        "a great circle does not determine band 8"
    );
    let good = fitter(
        4,
        ShBasis::Tournier07,
        false,
        &random_directions(&mut rng, 40),
        0.0,
    );
    match good.try_fit(&[0.0; 39]) {
        Err(Error::Data {
            problem:
                crate::error::Problem::Count {
                    expected: 40,
                    found: 39,
                },
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
}

/// The point set that `rotate_sh` fits on recovers every series to rounding: this is
/// what caught nalgebra's inaccurate SVD (legacy tournier07, band 8: 8e-8).
#[test]
fn rotation_point_set_recovers_coefficients_for_every_band() {
    let mut rng = Rng::new(33);
    for band in (0..=16).step_by(2) {
        let points = fibonacci_sphere(3 * sh_count(band) + 30);
        for (basis, legacy) in ALL_BASES {
            let f = fitter(band, basis, legacy, &points, 0.0);
            let w = rng.coefficients(sh_count(band));
            let back = f.fit(&f.fitted_values(&w));
            let err = w
                .iter()
                .zip(&back)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(
                err < 1e-13,
                "band {band} {basis:?} legacy={legacy}: {err:.3e}"
            );
        }
    }
}
