//! Rounding allowances of the interval and affine glyph ranges, in unit roundoffs u
//! (2^-24 for float32). build.rs includes this file with `#[path]` and bakes the numbers
//! into each variant's shaders; the CPU mirror in `interval.rs` uses the same ones, so
//! both widen their ranges alike.
//!
//! A range is widened by `f_rounding_units * u * abs_sum * m^n` for f, where abs_sum is
//! the sum of |stored entry| * multiplicity and m the largest coordinate magnitude on the
//! segment (so abs_sum * m^n bounds sum_k |c_k| |monomial_k|, the scale every rounding of
//! the monomial sum is relative to), plus `radius_rounding_units * u * |q|^(n+1)` (and its
//! offset term) for the powers of |q|.
use super::monomials::{monomials, multiplicity};

/// The largest number of stored tensor entries `glyph_load` folds into one monomial
/// coefficient: one product by the multiplicity for symmetric tensors (Eq. 5), a sum of
/// up to max multiplicity entries for non-symmetric ones (Eq. 4).
pub(crate) fn load_terms(order: u32, symmetric: bool) -> u64 {
    if symmetric {
        1
    } else {
        monomials(order)
            .into_iter()
            .map(multiplicity)
            .max()
            .unwrap_or(1)
    }
}

/// Unit roundoffs of the rounding bound of f's range. Per monomial at most 2n roundings
/// for the powers and their product and one for the coefficient; K for the sum of the K
/// monomials; loading; the segment's coordinates (mid + s dir, within about 7 u m each,
/// moving f by at most n times that); an affine product rounds about four times where an
/// interval product rounds once. Doubled to cover second-order terms and contracted
/// multiply-adds.
pub fn f_rounding_units(order: u32, symmetric: bool) -> f64 {
    let monomial_count = monomials(order).len() as f64;
    let n = order as f64;
    2.0 * (monomial_count + 20.0 * n + 16.0 + load_terms(order, symmetric) as f64)
}

/// Unit roundoffs of the rounding bound of |q|^(n+1) and w |q|^n: the quadratic |q(s)|^2,
/// n + 1 products and a square root, and the secant and tangent bound of the affine form.
pub fn radius_rounding_units(order: u32) -> f64 {
    8.0 * (order as f64 + 1.0) + 32.0
}
