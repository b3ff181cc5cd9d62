//! Normalised associated Legendre functions divided by sin^m(theta):
//! Q_l^m(z) = N_l^m P_l^m(z) / (1 - z^2)^(m/2), N_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!),
//! with the Condon-Shortley phase (-1)^m inside P_l^m. Q_l^m is a polynomial in
//! z = cos(theta) of degree l - m.
//!
//! The recurrences are the standard stable ones for fully normalised functions
//! (e.g. Press et al., Numerical Recipes 3rd ed., Sec. 6.7, Eqs. 6.7.9-6.7.10, with the
//! factor sin^m taken out): no factorials appear, so nothing overflows at high l.
//! - sectoral: Q_m^m = -sqrt((2m+1)/(2m)) Q_(m-1)^(m-1), Q_0^0 = 1/sqrt(4 pi);
//! - first step: Q_(m+1)^m = sqrt(2m+3) z Q_m^m;
//! - three-term: Q_l^m = a_lm (z Q_(l-1)^m - b_lm Q_(l-2)^m) with
//!   a_lm = sqrt((4l^2-1)/(l^2-m^2)), b_lm = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1)).
//!
//! The coefficient functions are shared with `tensor`, which runs the same recurrences
//! on polynomials (there z Q is a product and b Q_(l-2) gains the factor r^2 = 1).
//! Evaluation at many directions takes them from [`Recurrence::shared`], computed once
//! (square roots are most of a band's evaluation otherwise); the values are the same
//! numbers the functions give, so the results do not change by a bit.
use std::sync::OnceLock;

use super::MAX_SH_BAND;

/// Q_0^0 = Y_0^0 = 1 / sqrt(4 pi).
pub(super) fn q00() -> f64 {
    0.5 / std::f64::consts::PI.sqrt()
}

/// Q_m^m / Q_(m-1)^(m-1) = -sqrt((2m+1)/(2m)) for m >= 1 (the minus sign is the
/// Condon-Shortley phase).
pub(super) fn sectoral_ratio(m: u32) -> f64 {
    let m = m as f64;
    -((2.0 * m + 1.0) / (2.0 * m)).sqrt()
}

/// Q_(m+1)^m / (z Q_m^m) = sqrt(2m+3).
pub(super) fn first_step(m: u32) -> f64 {
    (2.0 * m as f64 + 3.0).sqrt()
}

/// (a_lm, b_lm) of the three-term recurrence, for l >= m + 2.
pub(super) fn three_term(l: u32, m: u32) -> (f64, f64) {
    let (l, m) = (l as f64, m as f64);
    let a = ((4.0 * l * l - 1.0) / (l * l - m * m)).sqrt();
    let lm1 = l - 1.0;
    let b = ((lm1 * lm1 - m * m) / (4.0 * lm1 * lm1 - 1.0)).sqrt();
    (a, b)
}

/// Flat index of (l, m), 0 <= m <= l, in a table over every l (odd ones included).
pub(crate) fn table_index(l: u32, m: u32) -> usize {
    (l * (l + 1) / 2 + m) as usize
}

/// Q_l^m(z) for every 0 <= m <= l <= band, at index `table_index(l, m)`.
pub(crate) fn q_table(band: u32, z: f64) -> Vec<f64> {
    let mut q = vec![0.0; table_index(band, band) + 1];
    let mut sectoral = q00();
    for m in 0..=band {
        if m > 0 {
            sectoral *= sectoral_ratio(m);
        }
        q[table_index(m, m)] = sectoral;
        if m == band {
            break;
        }
        let mut prev = sectoral;
        let mut cur = first_step(m) * z * sectoral;
        q[table_index(m + 1, m)] = cur;
        for l in m + 2..=band {
            let (a, b) = three_term(l, m);
            let next = a * (z * cur - b * prev);
            q[table_index(l, m)] = next;
            (prev, cur) = (cur, next);
        }
    }
    q
}

/// The recurrence factors for every 0 <= m <= l <= [`MAX_SH_BAND`], computed once for
/// the process; past that band each is computed when asked for.
pub(super) struct Recurrence {
    /// `sectoral_ratio(m)` at index m (index 0 unused).
    sectoral: Vec<f64>,
    /// `first_step(m)` at index m.
    first: Vec<f64>,
    /// `three_term(l, m)` at `table_index(l, m)` (unused where l < m + 2).
    three_term: Vec<(f64, f64)>,
}

impl Recurrence {
    /// The process-wide table.
    pub(super) fn shared() -> &'static Self {
        static TABLE: OnceLock<Recurrence> = OnceLock::new();
        TABLE.get_or_init(|| {
            let mut three = vec![(0.0, 0.0); table_index(MAX_SH_BAND, MAX_SH_BAND) + 1];
            for l in 2..=MAX_SH_BAND {
                for m in 0..=l - 2 {
                    three[table_index(l, m)] = three_term(l, m);
                }
            }
            Self {
                sectoral: (0..=MAX_SH_BAND)
                    .map(|m| if m == 0 { 1.0 } else { sectoral_ratio(m) })
                    .collect(),
                first: (0..=MAX_SH_BAND).map(first_step).collect(),
                three_term: three,
            }
        })
    }

    /// [`sectoral_ratio`]`(m)`, m >= 1.
    pub(super) fn sectoral(&self, m: u32) -> f64 {
        self.sectoral
            .get(m as usize)
            .copied()
            .unwrap_or_else(|| sectoral_ratio(m))
    }

    /// [`first_step`]`(m)`.
    pub(super) fn first(&self, m: u32) -> f64 {
        self.first
            .get(m as usize)
            .copied()
            .unwrap_or_else(|| first_step(m))
    }

    /// [`three_term`]`(l, m)`, l >= m + 2. (`table_index` grows with l, so every l past
    /// the table's band falls past its end.)
    pub(super) fn three_term(&self, l: u32, m: u32) -> (f64, f64) {
        self.three_term
            .get(table_index(l, m))
            .copied()
            .unwrap_or_else(|| three_term(l, m))
    }
}
