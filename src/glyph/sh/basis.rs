//! The four real SH bases of the scene format as `factor * Q_l^|m| * Re/Im (x+iy)^|m|`.
//!
//! From Y_l^m = Q_l^m (x + iy)^m for m >= 0 and Y_l^(-m) = (-1)^m conj(Y_l^m):
//! - `tournier07`: m < 0: sqrt2 Im Y_l^|m|; m > 0: sqrt2 Re Y_l^m (legacy: no sqrt2);
//! - `descoteaux07`: m < 0: sqrt2 Re Y_l^m = sqrt2 (-1)^m Re Y_l^|m|;
//!   m > 0: sqrt2 Im Y_l^m (legacy: m < 0 is sqrt2 Re Y_l^|m|, without (-1)^m);
//! - every basis: m = 0 is Y_l^0 = Q_l^0.
use glam::DVec3;

use super::legendre::{q_table, table_index};
use super::{sh_count, sh_orders};
use crate::glyph::sh::ShBasis;

/// Which part of (x + iy)^|m| = sin^|m|(theta) e^(i |m| phi) a basis function carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Part {
    /// cos(|m| phi) (and every m = 0 function).
    Re,
    /// sin(|m| phi).
    Im,
}

/// (part, factor) of basis function (l, m): B_l^m = factor * Q_l^|m| * part((x+iy)^|m|).
/// Independent of l.
pub(super) fn basis_term(basis: ShBasis, legacy: bool, m: i32) -> (Part, f64) {
    let sqrt2 = std::f64::consts::SQRT_2;
    if m == 0 {
        return (Part::Re, 1.0);
    }
    match basis {
        ShBasis::Tournier07 => {
            let part = if m < 0 { Part::Im } else { Part::Re };
            (part, if legacy { 1.0 } else { sqrt2 })
        }
        ShBasis::Descoteaux07 if m > 0 => (Part::Im, sqrt2),
        ShBasis::Descoteaux07 => {
            let phase = if legacy || m % 2 == 0 { 1.0 } else { -1.0 };
            (Part::Re, phase * sqrt2)
        }
    }
}

/// The signed order m at which `basis` keeps part `part` of (x+iy)^k, k >= 0.
pub(super) fn signed_order(basis: ShBasis, k: u32, part: Part) -> i32 {
    let k = k as i32;
    match (basis, part) {
        (ShBasis::Tournier07, Part::Re) | (ShBasis::Descoteaux07, Part::Im) => k,
        (ShBasis::Tournier07, Part::Im) | (ShBasis::Descoteaux07, Part::Re) => -k,
    }
}

/// (Re, Im) of (x + iy)^k for k = 0..=band.
fn azimuthal_powers(band: u32, u: DVec3) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(band as usize + 1);
    let (mut re, mut im) = (1.0, 0.0);
    for _ in 0..=band {
        out.push((re, im));
        (re, im) = (re * u.x - im * u.y, re * u.y + im * u.x);
    }
    out
}

/// Values of every basis function, in coefficient order, at direction u: even bands
/// 0, 2, ..., band (an odd band adds nothing over band - 1). u is normalised first;
/// the zero vector is taken as +z.
pub fn sh_basis_values(band: u32, basis: ShBasis, legacy: bool, u: DVec3) -> Vec<f64> {
    let u = u.normalize_or(DVec3::Z);
    let q = q_table(band, u.z);
    let powers = azimuthal_powers(band, u);
    let mut values = Vec::with_capacity(sh_count(band));
    for (l, m) in sh_orders(band) {
        let k = m.unsigned_abs();
        let (part, factor) = basis_term(basis, legacy, m);
        let (re, im) = powers[k as usize];
        let trig = if part == Part::Re { re } else { im };
        values.push(factor * q[table_index(l, k)] * trig);
    }
    values
}

/// The SH series `sum_j coeffs[j] B_j(u)`. Coefficients past `sh_count(band)` are
/// ignored and missing ones count as zero (use `check_coefficients` to reject them).
pub fn sh_eval(band: u32, basis: ShBasis, legacy: bool, coeffs: &[f64], u: DVec3) -> f64 {
    sh_basis_values(band, basis, legacy, u)
        .iter()
        .zip(coeffs)
        .map(|(b, c)| b * c)
        .sum()
}
