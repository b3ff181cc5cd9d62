//! Basis conversion and rotation, judged by function values.
use glam::{DMat3, DVec3};

use super::{ALL_BASES, Rng, test_directions};
use crate::Error;
use crate::glyph::polynomial::GlyphPolynomial;
use crate::glyph::rotate::rotate_symmetric_tensor;
use crate::glyph::sh::ShBasis;
use crate::glyph::sh::{convert_basis, rotate_sh, sh_count, sh_eval, sh_to_tensor};
use crate::glyph::{Symmetry, TensorLayout};

fn ok<T>(r: crate::Result<T>) -> T {
    match r {
        Ok(v) => v,
        Err(e) => panic!("{e}"),
    }
}

fn tensor_value(order: u32, t: &[f64], u: DVec3) -> f64 {
    let layout = TensorLayout {
        order,
        symmetry: Symmetry::Symmetric,
    };
    ok(GlyphPolynomial::from_tensor(layout, t)).eval(u)
}

#[test]
fn conversion_preserves_values_and_round_trips() {
    let mut rng = Rng::new(20);
    for band in [0, 2, 8, 12] {
        for from in ALL_BASES {
            let w = rng.coefficients(sh_count(band));
            for to in ALL_BASES {
                let converted = ok(convert_basis(band, from, to, &w));
                for u in test_directions(&mut rng, 10) {
                    let a = sh_eval(band, from.0, from.1, &w, u);
                    let b = sh_eval(band, to.0, to.1, &converted, u);
                    assert!((a - b).abs() < 1e-12, "{from:?} -> {to:?} band {band}");
                }
                let back = ok(convert_basis(band, to, from, &converted));
                w.iter()
                    .zip(&back)
                    .for_each(|(x, y)| assert!((x - y).abs() < 1e-14, "{from:?} <-> {to:?}"));
            }
        }
    }
}

#[test]
fn conversion_between_modern_bases_is_a_signed_permutation() {
    // descoteaux07 (l, -m) = (-1)^m tournier07 (l, m); descoteaux07 (l, m) = tournier07 (l, -m).
    let w: Vec<f64> = (0..15).map(|i| i as f64 + 1.0).collect();
    let d = ok(convert_basis(
        4,
        (ShBasis::Tournier07, false),
        (ShBasis::Descoteaux07, false),
        &w,
    ));
    // Band 2 block: tournier (m = -2..2) = 2 3 4 5 6.
    assert_eq!(&d[1..6], &[6.0, -5.0, 4.0, 3.0, 2.0]);
}

fn check_rotation(r: DMat3, rng: &mut Rng, label: &str) {
    for band in [2, 4, 8, 12] {
        for (basis, legacy) in ALL_BASES {
            let w = rng.coefficients(sh_count(band));
            let rotated = ok(rotate_sh(band, basis, legacy, &w, r));
            for u in test_directions(rng, 20) {
                let want = sh_eval(band, basis, legacy, &w, r.transpose() * u);
                let got = sh_eval(band, basis, legacy, &rotated, u);
                assert!(
                    (got - want).abs() < 1e-11,
                    "{label}: band {band} {basis:?} legacy={legacy}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn rotated_series_is_f_of_r_transpose_u() {
    let mut rng = Rng::new(21);
    for _ in 0..3 {
        let r = rng.rotation();
        check_rotation(r, &mut rng, "rotation");
    }
    let reflection = rng.reflection();
    assert!((reflection.determinant() + 1.0).abs() < 1e-12);
    check_rotation(reflection, &mut rng, "reflection");
}

#[test]
fn rotated_tensor_is_f_of_r_transpose_u() {
    let mut rng = Rng::new(22);
    for order in 0..=12 {
        let t = rng.coefficients(crate::glyph::monomials::symmetric_count(order));
        for r in [rng.rotation(), rng.reflection()] {
            let rotated = ok(rotate_symmetric_tensor(order, &t, r));
            if order == 0 {
                assert_eq!(rotated, t);
                continue;
            }
            for u in test_directions(&mut rng, 20) {
                let want = tensor_value(order, &t, r.transpose() * u);
                let got = tensor_value(order, &rotated, u);
                assert!((got - want).abs() < 1e-9, "order {order}: {got} vs {want}");
            }
        }
    }
}

#[test]
fn rotation_commutes_with_the_tensor_map() {
    let mut rng = Rng::new(23);
    let r = rng.rotation();
    for (basis, legacy) in ALL_BASES {
        let w = rng.coefficients(sh_count(6));
        let (order, t) = ok(sh_to_tensor(6, basis, legacy, &w));
        let via_sh = ok(sh_to_tensor(
            6,
            basis,
            legacy,
            &ok(rotate_sh(6, basis, legacy, &w, r)),
        ))
        .1;
        let via_tensor = ok(rotate_symmetric_tensor(order, &t, r));
        via_sh
            .iter()
            .zip(&via_tensor)
            .for_each(|(a, b)| assert!((a - b).abs() < 1e-10, "{a} vs {b}"));
    }
}

#[test]
fn rotation_rejects_bad_input() {
    let invalid = |r: crate::Result<Vec<f64>>| matches!(r, Err(Error::Data { .. }));
    let shear = DMat3::from_cols(DVec3::X, DVec3::new(0.1, 1.0, 0.0), DVec3::Z);
    assert!(invalid(rotate_sh(
        2,
        ShBasis::Tournier07,
        false,
        &[0.0; 6],
        shear
    )));
    assert!(invalid(rotate_symmetric_tensor(2, &[0.0; 6], shear)));
    assert!(invalid(rotate_sh(
        2,
        ShBasis::Tournier07,
        false,
        &[0.0; 5],
        DMat3::IDENTITY
    )));
    assert!(invalid(rotate_symmetric_tensor(
        2,
        &[0.0; 5],
        DMat3::IDENTITY
    )));
    assert!(invalid(rotate_symmetric_tensor(
        21,
        &[0.0; 253],
        DMat3::IDENTITY
    )));
    let nan = DMat3::from_cols(DVec3::X, DVec3::Y, DVec3::new(0.0, 0.0, f64::NAN));
    assert!(invalid(rotate_symmetric_tensor(2, &[0.0; 6], nan)));
}
