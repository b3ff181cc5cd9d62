//! The four real SH bases of the scene format as `factor * Q_l^|m| * Re/Im (x+iy)^|m|`.
//!
//! From Y_l^m = Q_l^m (x + iy)^m for m >= 0 and Y_l^(-m) = (-1)^m conj(Y_l^m):
//! - `tournier07`: m < 0: sqrt2 Im Y_l^|m|; m > 0: sqrt2 Re Y_l^m (legacy: no sqrt2);
//! - `descoteaux07`: m < 0: sqrt2 Re Y_l^m = sqrt2 (-1)^m Re Y_l^|m|;
//!   m > 0: sqrt2 Im Y_l^m (legacy: m < 0 is sqrt2 Re Y_l^|m|, without (-1)^m);
//! - every basis: m = 0 is Y_l^0 = Q_l^0.
use glam::DVec3;

use super::legendre::{Recurrence, q00};
use super::{MAX_SH_BAND, sh_count, sh_index};
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

/// Evaluates every basis function of one (band, basis, legacy) at a direction, with no
/// heap allocation: the values are written in place, order by order (m = 0, 1, ...):
/// for each |m| the azimuthal power (x + iy)^|m| and the column Q_l^|m|, l = |m|..band,
/// are carried as scalars instead of tables, and the recurrence factors come from a
/// table made once (`legendre::Recurrence`). Every value is the same product of the same
/// numbers as when read from a whole table of Q_l^m (`legendre::q_table`, which this
/// replaced here), so the results are the same to the bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShEvaluator {
    band: u32,
    basis: ShBasis,
    legacy: bool,
}

impl ShEvaluator {
    /// An evaluator of the even bands 0, 2, ..., band (an odd band adds nothing over
    /// band - 1).
    pub fn new(band: u32, basis: ShBasis, legacy: bool) -> Self {
        Self {
            band,
            basis,
            legacy,
        }
    }

    /// The number of values: `sh_count(band)`.
    pub fn count(&self) -> usize {
        sh_count(self.band)
    }

    /// Writes the value of every basis function at direction u into `out`, in
    /// coefficient order; u is normalised first, the zero vector taken as +z. Only the
    /// first `out.len()` values are written where `out` is shorter than [`Self::count`].
    pub fn values_into(&self, u: DVec3, out: &mut [f64]) {
        let u = u.normalize_or(DVec3::Z);
        let factors = Recurrence::shared();
        let mut put = |l: u32, k: u32, q: f64, (re, im): (f64, f64)| {
            if !l.is_multiple_of(2) {
                return;
            }
            let orders = [k as i32, -(k as i32)];
            for &m in &orders[..if k == 0 { 1 } else { 2 }] {
                let (part, factor) = basis_term(self.basis, self.legacy, m);
                let trig = if part == Part::Re { re } else { im };
                if let Some(slot) = out.get_mut(sh_index(l, m)) {
                    *slot = factor * q * trig;
                }
            }
        };
        let (mut re, mut im) = (1.0, 0.0);
        let mut sectoral = q00();
        for k in 0..=self.band {
            if k > 0 {
                sectoral *= factors.sectoral(k);
                (re, im) = (re * u.x - im * u.y, re * u.y + im * u.x);
            }
            put(k, k, sectoral, (re, im));
            if k == self.band {
                break;
            }
            let mut prev = sectoral;
            let mut cur = factors.first(k) * u.z * sectoral;
            put(k + 1, k, cur, (re, im));
            for l in k + 2..=self.band {
                let (a, b) = factors.three_term(l, k);
                let next = a * (u.z * cur - b * prev);
                put(l, k, next, (re, im));
                (prev, cur) = (cur, next);
            }
        }
    }

    /// The SH series `sum_j coeffs[j] B_j(u)`, summed in coefficient order. Coefficients
    /// past [`Self::count`] are ignored and missing ones count as zero.
    pub fn eval(&self, coeffs: &[f64], u: DVec3) -> f64 {
        /// Values held on the stack: every band this module accepts.
        const ON_STACK: usize = sh_count(MAX_SH_BAND);
        let count = self.count();
        let mut stack = [0.0; ON_STACK];
        let mut heap = Vec::new();
        let values = if count <= ON_STACK {
            &mut stack[..count]
        } else {
            heap.resize(count, 0.0);
            &mut heap[..]
        };
        self.values_into(u, values);
        values.iter().zip(coeffs).map(|(b, c)| b * c).sum()
    }
}

/// Values of every basis function, in coefficient order, at direction u: even bands
/// 0, 2, ..., band (an odd band adds nothing over band - 1). u is normalised first;
/// the zero vector is taken as +z.
pub fn sh_basis_values(band: u32, basis: ShBasis, legacy: bool, u: DVec3) -> Vec<f64> {
    let evaluator = ShEvaluator::new(band, basis, legacy);
    let mut values = vec![0.0; evaluator.count()];
    evaluator.values_into(u, &mut values);
    values
}

/// The SH series `sum_j coeffs[j] B_j(u)`. Coefficients past `sh_count(band)` are
/// ignored and missing ones count as zero (use `check_coefficients` to reject them).
pub fn sh_eval(band: u32, basis: ShBasis, legacy: bool, coeffs: &[f64], u: DVec3) -> f64 {
    ShEvaluator::new(band, basis, legacy).eval(coeffs, u)
}
