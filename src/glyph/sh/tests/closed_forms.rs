//! The basis values against references that share no code with the implementation:
//! the Cartesian closed forms of the complex harmonics for l = 0, 2, 4 (standard tables,
//! Condon-Shortley phase), and for every l an explicit sum for the associated Legendre
//! function in spherical angles. The real bases are then assembled literally from the
//! scene format's definitions, using Y_l^(-m) = (-1)^m conj(Y_l^m).
use std::f64::consts::{PI, SQRT_2};

use glam::DVec3;

use super::{ALL_BASES, Rng, test_directions};
use crate::glyph::sh::ShBasis;
use crate::glyph::sh::{sh_basis_values, sh_count, sh_eval, sh_index, sh_orders};

/// A complex number as (re, im).
type Complex = (f64, f64);

fn cmul(a: Complex, b: Complex) -> Complex {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

fn cpow(a: Complex, k: u32) -> Complex {
    (0..k).fold((1.0, 0.0), |acc, _| cmul(acc, a))
}

/// Y_l^m for l in {0, 2, 4}, 0 <= m <= l, from the textbook Cartesian table.
fn table_harmonic(l: u32, m: u32, u: DVec3) -> Complex {
    let (z, w) = (u.z, (u.x, u.y));
    let real = |c: f64| (c, 0.0);
    let times = |c: f64, k: u32| {
        let p = cpow(w, k);
        (c * p.0, c * p.1)
    };
    match (l, m) {
        (0, 0) => real(0.5 * (1.0 / PI).sqrt()),
        (2, 0) => real(0.25 * (5.0 / PI).sqrt() * (3.0 * z * z - 1.0)),
        (2, 1) => times(-0.5 * (15.0 / (2.0 * PI)).sqrt() * z, 1),
        (2, 2) => times(0.25 * (15.0 / (2.0 * PI)).sqrt(), 2),
        (4, 0) => real(3.0 / 16.0 * (1.0 / PI).sqrt() * (35.0 * z.powi(4) - 30.0 * z * z + 3.0)),
        (4, 1) => times(-3.0 / 8.0 * (5.0 / PI).sqrt() * z * (7.0 * z * z - 3.0), 1),
        (4, 2) => times(
            3.0 / 8.0 * (5.0 / (2.0 * PI)).sqrt() * (7.0 * z * z - 1.0),
            2,
        ),
        (4, 3) => times(-3.0 / 8.0 * (35.0 / PI).sqrt() * z, 3),
        (4, 4) => times(3.0 / 16.0 * (35.0 / (2.0 * PI)).sqrt(), 4),
        _ => (f64::NAN, f64::NAN),
    }
}

fn factorial(n: u32) -> f64 {
    (1..=n).map(f64::from).product()
}

fn binomial(n: u32, k: u32) -> f64 {
    factorial(n) / (factorial(k) * factorial(n - k))
}

/// (P_l^m(x), bound) with P_l^m(x) = (-1)^m (1-x^2)^(m/2) d^m/dx^m P_l(x) and
/// P_l(x) = 2^-l sum_k (-1)^k C(l,k) C(2l-2k,l) x^(l-2k) (Rodrigues' formula expanded).
/// `bound` is the same sum with absolute values: the scale of its rounding error.
fn explicit_legendre(l: u32, m: u32, x: f64) -> (f64, f64) {
    let (mut sum, mut bound) = (0.0, 0.0);
    for k in 0..=l / 2 {
        let p = l - 2 * k;
        if p < m {
            continue;
        }
        let term = binomial(l, k) * binomial(2 * l - 2 * k, l) * factorial(p) / factorial(p - m)
            * x.powi((p - m) as i32);
        sum += if k.is_multiple_of(2) { term } else { -term };
        bound += term.abs();
    }
    let scale = (1.0 - x * x).powf(m as f64 / 2.0) / 2f64.powi(l as i32);
    let phase = if m.is_multiple_of(2) { 1.0 } else { -1.0 };
    (phase * scale * sum, scale * bound)
}

/// (Y_l^m(theta, phi), error scale) for m >= 0 from the explicit sum, in angles.
fn explicit_harmonic(l: u32, m: u32, u: DVec3) -> (Complex, f64) {
    let theta = u.z.clamp(-1.0, 1.0).acos();
    let phi = u.y.atan2(u.x);
    let norm = ((2 * l + 1) as f64 / (4.0 * PI) * factorial(l - m) / factorial(l + m)).sqrt();
    let (p, bound) = explicit_legendre(l, m, theta.cos());
    let mphi = m as f64 * phi;
    ((norm * p * mphi.cos(), norm * p * mphi.sin()), norm * bound)
}

/// Y_l^m for any sign of m, from Y_l^(-m) = (-1)^m conj(Y_l^m).
fn signed_harmonic(harmonic: &dyn Fn(u32, u32) -> Complex, l: u32, m: i32) -> Complex {
    let y = harmonic(l, m.unsigned_abs());
    if m >= 0 {
        y
    } else {
        let phase = if m % 2 == 0 { 1.0 } else { -1.0 };
        (phase * y.0, -phase * y.1)
    }
}

/// Basis function (l, m) literally as docs/scene-format.md defines it.
fn contract_basis(
    harmonic: &dyn Fn(u32, u32) -> Complex,
    basis: ShBasis,
    legacy: bool,
    l: u32,
    m: i32,
) -> f64 {
    let y = |m: i32| signed_harmonic(harmonic, l, m);
    let a = m.abs();
    match (basis, m.signum()) {
        (_, 0) => y(0).0,
        (ShBasis::Tournier07, -1) => (if legacy { 1.0 } else { SQRT_2 }) * y(a).1,
        (ShBasis::Tournier07, _) => (if legacy { 1.0 } else { SQRT_2 }) * y(m).0,
        (ShBasis::Descoteaux07, -1) if legacy => SQRT_2 * y(a).0,
        (ShBasis::Descoteaux07, -1) => SQRT_2 * y(m).0,
        (ShBasis::Descoteaux07, _) => SQRT_2 * y(m).1,
    }
}

#[test]
fn bands_0_2_4_match_the_cartesian_tables() {
    let mut rng = Rng::new(1);
    for u in test_directions(&mut rng, 50) {
        let table = |l: u32, m: u32| table_harmonic(l, m, u);
        for (basis, legacy) in super::ALL_BASES {
            let values = sh_basis_values(4, basis, legacy, u);
            assert_eq!(values.len(), 15);
            for (l, m) in sh_orders(4) {
                let want = contract_basis(&table, basis, legacy, l, m);
                let got = values[sh_index(l, m)];
                assert!(
                    (got - want).abs() < 1e-14,
                    "{basis:?} legacy={legacy} (l={l}, m={m}) at {u}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn every_band_to_16_matches_the_explicit_legendre_sum() {
    let mut rng = Rng::new(2);
    for u in test_directions(&mut rng, 40) {
        let explicit = |l: u32, m: u32| explicit_harmonic(l, m, u).0;
        for (basis, legacy) in ALL_BASES {
            let values = sh_basis_values(16, basis, legacy, u);
            for (l, m) in sh_orders(16) {
                let want = contract_basis(&explicit, basis, legacy, l, m);
                // The explicit sum cancels heavily at high l; its own rounding bounds
                // the comparison (a few ulps of the sum of absolute terms).
                let scale = explicit_harmonic(l, m.unsigned_abs(), u).1;
                let tol = 1e-14 * (1.0 + 4.0 * scale);
                let got = values[sh_index(l, m)];
                assert!(
                    (got - want).abs() < tol,
                    "{basis:?} legacy={legacy} (l={l}, m={m}) at {u}: {got} vs {want}, tol {tol:.1e}"
                );
            }
        }
    }
}

#[test]
fn counts_indices_and_direction_normalisation() {
    assert_eq!(
        [0, 2, 4, 6, 8, 10, 12].map(sh_count),
        [1, 6, 15, 28, 45, 66, 91]
    );
    assert_eq!(sh_count(3), sh_count(2));
    assert_eq!(sh_index(0, 0), 0);
    assert_eq!(sh_index(2, -2), 1);
    assert_eq!(sh_index(4, 4), 14);
    assert_eq!(sh_index(8, 8), 44);
    let listed: Vec<usize> = sh_orders(8).map(|(l, m)| sh_index(l, m)).collect();
    assert_eq!(listed, (0..45).collect::<Vec<_>>());

    let mut rng = Rng::new(3);
    let coeffs = rng.coefficients(45);
    let u = rng.direction();
    let a = sh_eval(8, ShBasis::Descoteaux07, false, &coeffs, u);
    let b = sh_eval(8, ShBasis::Descoteaux07, false, &coeffs, 3.5 * u);
    assert!((a - b).abs() < 1e-14);
    // Antipodal symmetry of even bands.
    let c = sh_eval(8, ShBasis::Descoteaux07, false, &coeffs, -u);
    assert!((a - c).abs() < 1e-13);
}
