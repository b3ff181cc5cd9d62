//! t = M w against the SH series, with M also rebuilt independently by least squares.
use std::sync::Arc;

use nalgebra::DMatrix;

use super::{ALL_BASES, Rng, test_directions};
use crate::Error;
use crate::error::Problem;
use crate::glyph::monomials::{monomials, multiplicity, symmetric_count};
use crate::glyph::polynomial::GlyphPolynomial;
use crate::glyph::sh::ShBasis;
use crate::glyph::sh::rotate::fibonacci_sphere;
use crate::glyph::sh::{sh_basis_values, sh_count, sh_eval, sh_to_tensor, sh_to_tensor_matrix};
use crate::glyph::{Symmetry, TensorLayout};

fn tensor_value(order: u32, t: &[f64], u: glam::DVec3) -> f64 {
    let layout = TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    };
    match GlyphPolynomial::from_tensor(layout, t) {
        Ok(p) => p.eval(u),
        Err(e) => panic!("tensor of order {order}: {e}"),
    }
}

#[test]
fn tensor_reproduces_the_series_for_every_band_and_basis() {
    // Measured: at most 1.1e-14 at band 12 and 3e-14 at band 16 (coefficients in [-1, 1]).
    let mut rng = Rng::new(10);
    for band in (0..=16).step_by(2) {
        for (basis, legacy) in ALL_BASES {
            let w = rng.coefficients(sh_count(band));
            let (order, t) = match sh_to_tensor(band, basis, legacy, &w) {
                Ok(pair) => pair,
                Err(e) => panic!("band {band}: {e}"),
            };
            assert_eq!(order, band.max(2));
            assert_eq!(t.len(), symmetric_count(order));
            for u in test_directions(&mut rng, 30) {
                let want = sh_eval(band, basis, legacy, &w, u);
                let got = tensor_value(order, &t, u);
                assert!(
                    (got - want).abs() < 1e-10,
                    "band {band} {basis:?} legacy={legacy} at {u}: {got} vs {want}"
                );
            }
        }
    }
}

/// M by least squares: monomials * multiplicities on a point set against SH values.
fn least_squares_matrix(band: u32, basis: ShBasis, legacy: bool) -> DMatrix<f64> {
    let order = band.max(2);
    let points = fibonacci_sphere(4 * symmetric_count(order) + 40);
    let monos = monomials(order);
    let a = DMatrix::from_fn(points.len(), monos.len(), |i, k| {
        let (u, m) = (points[i], monos[k]);
        multiplicity(m) as f64 * u.x.powi(m.a as i32) * u.y.powi(m.b as i32) * u.z.powi(m.c as i32)
    });
    let b_rows: Vec<f64> = points
        .iter()
        .flat_map(|u| sh_basis_values(band, basis, legacy, *u))
        .collect();
    let b = DMatrix::from_row_slice(points.len(), sh_count(band), &b_rows);
    // Householder QR: nalgebra 0.35's SVD is not accurate enough here (see fit.rs).
    // Measured agreement with the closed form: 1.5e-15 of max |M| at band 12.
    let qr = a.qr();
    match qr.r().solve_upper_triangular(&(qr.q().transpose() * b)) {
        Some(m) => m,
        None => panic!("least squares: singular monomial matrix"),
    }
}

/// Extreme singular values, from the symmetric eigenvalues of M^T M (M is square and
/// well enough conditioned for that to lose nothing that matters here).
fn singular_values(m: &DMatrix<f64>) -> (f64, f64) {
    let eig = (m.transpose() * m).symmetric_eigen().eigenvalues;
    (eig.max().sqrt(), eig.min().sqrt())
}

#[test]
fn closed_form_matrix_agrees_with_least_squares_and_conditioning_is_reported() {
    for band in [0, 2, 4, 8, 12] {
        for (basis, legacy) in ALL_BASES {
            let exact = match sh_to_tensor_matrix(band, basis, legacy) {
                Ok(m) => m,
                Err(e) => panic!("{e}"),
            };
            let exact_m = DMatrix::from_row_slice(exact.rows(), exact.cols(), &exact.matrix);
            let fitted = least_squares_matrix(band, basis, legacy);
            let scale = exact_m.amax();
            let diff = (&exact_m - &fitted).amax();
            assert!(
                diff < 1e-12 * scale,
                "band {band} {basis:?} legacy={legacy}: max |M - M_lsq| = {diff:.3e}"
            );
            if band == 12 && basis == ShBasis::Tournier07 && !legacy {
                let (smax, smin) = singular_values(&exact_m);
                println!(
                    "band 12 M: singular values {smax:.3e} .. {smin:.3e}, cond {:.3e}; \
                     max |M - M_lsq| / max |M| = {:.3e}",
                    smax / smin,
                    diff / scale
                );
                // Measured 2.5e2; a bound with margin, so that a wrong (near-dependent)
                // column would show up here.
                assert!(smax / smin < 1e3);
            }
        }
    }
}

#[test]
fn matrices_are_cached_and_bad_input_is_rejected() {
    let a = sh_to_tensor_matrix(8, ShBasis::Descoteaux07, true);
    let b = sh_to_tensor_matrix(8, ShBasis::Descoteaux07, true);
    let c = sh_to_tensor_matrix(8, ShBasis::Descoteaux07, false);
    match (a, b, c) {
        (Ok(a), Ok(b), Ok(c)) => {
            assert!(Arc::ptr_eq(&a, &b));
            assert!(!Arc::ptr_eq(&a, &c));
            assert_eq!((a.rows(), a.cols(), a.matrix.len()), (45, 45, 45 * 45));
        }
        _ => panic!("band 8 must be accepted"),
    }
    let problem = |r: crate::Result<(u32, Vec<f64>)>| match r {
        Err(Error::Data { problem, .. }) => problem,
        other => panic!("expected Error::Data, got {other:?}"),
    };
    let short = sh_to_tensor(8, ShBasis::Tournier07, false, &[0.0; 44]);
    assert_eq!(
        short.as_ref().map_err(ToString::to_string).err().as_deref(),
        Some("SH coefficients: expected 45, found 44")
    );
    assert_eq!(
        problem(short),
        Problem::Count {
            expected: 45,
            found: 44
        }
    );
    assert_eq!(
        problem(sh_to_tensor(7, ShBasis::Tournier07, false, &[0.0; 36])),
        Problem::Odd { value: 7 }
    );
    assert!(matches!(
        problem(sh_to_tensor(18, ShBasis::Tournier07, false, &[0.0; 190])),
        Problem::OutOfRange { max: 16.0, .. }
    ));
    let mut w = vec![0.0; 6];
    w[3] = f64::NAN;
    assert!(matches!(
        problem(sh_to_tensor(2, ShBasis::Tournier07, false, &w)),
        Problem::NotFinite { index: 3, .. }
    ));
}

#[test]
fn band_0_is_the_sphere_tensor() {
    let w0 = 2.0 * (std::f64::consts::PI).sqrt(); // w0 Y_0^0 = 1
    let (order, t) = match sh_to_tensor(0, ShBasis::Tournier07, false, &[w0]) {
        Ok(pair) => pair,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(order, 2);
    let identity = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0];
    t.iter()
        .zip(identity)
        .for_each(|(a, b)| assert!((a - b).abs() < 1e-15, "{t:?}"));
}
