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
