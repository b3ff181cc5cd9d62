//! TEMPORARY stand-ins for `crate::glyph::sh`, which is being written on the `sh` branch.
//! Only the names this module uses, with the same signatures; at the merge this file is
//! deleted and `use super::sh_shim as sh;` in this module's users becomes
//! `use crate::glyph::sh;`.
//!
//! `rotate_symmetric_tensor` is real (it goes through the full tensor, 3^n entries), so
//! that tensor volumes work before the merge; the SH functions report that SH support is
//! not in this build yet.
use glam::DMat3;

use super::reorient::rotate_full_tensor;
use crate::glyph::monomials::{
    Monomial, monomial_index, monomials, nonsymmetric_count, nonsymmetric_entry_monomial,
};
use crate::io::scene::ShBasis;
use crate::{Error, Result};

fn not_available(what: &str) -> Error {
    Error::Invalid(format!(
        "{what}: SH volumes need the SH module (crate::glyph::sh), which is not in this build yet"
    ))
}

/// Coefficients of an SH series up to even band L: (L+1)(L+2)/2.
pub fn sh_count(band: u32) -> usize {
    crate::glyph::monomials::symmetric_count(band)
}

/// g(u) = f(R^T u) for SH coefficients: not available before the merge.
pub fn rotate_sh(
    _band: u32,
    _basis: ShBasis,
    _legacy: bool,
    _coeffs: &[f64],
    _r: DMat3,
) -> Result<Vec<f64>> {
    Err(not_available("rotating SH coefficients"))
}

/// SH series to the symmetric tensor of the same order: not available before the merge.
pub fn sh_to_tensor(
    _band: u32,
    _basis: ShBasis,
    _legacy: bool,
    _coeffs: &[f64],
) -> Result<(u32, Vec<f64>)> {
    Err(not_available("converting SH to a tensor"))
}

/// g(u) = f(R^T u) for a symmetric tensor in the scene format's unique-coefficient order:
/// expanded to all 3^n entries, rotated index by index, and read back at the sorted tuples.
pub fn rotate_symmetric_tensor(order: u32, coeffs: &[f64], r: DMat3) -> Result<Vec<f64>> {
    let unique = monomials(order);
    if coeffs.len() != unique.len() {
        return Err(Error::Invalid(format!(
            "symmetric tensor of order {order} needs {} coefficients, got {}",
            unique.len(),
            coeffs.len()
        )));
    }
    let full: Vec<f64> = (0..nonsymmetric_count(order))
        .map(|flat| coeffs[monomial_index(order, nonsymmetric_entry_monomial(order, flat))])
        .collect();
    let rotated = rotate_full_tensor(order, &full, r)?;
    Ok(unique
        .into_iter()
        .map(|m| rotated[sorted_tuple_flat_index(m)])
        .collect())
}

/// Row-major index of the sorted tuple 0..0 1..1 2..2 of monomial m.
fn sorted_tuple_flat_index(m: Monomial) -> usize {
    let digits = std::iter::repeat_n(0, m.a as usize)
        .chain(std::iter::repeat_n(1, m.b as usize))
        .chain(std::iter::repeat_n(2, m.c as usize));
    digits.fold(0, |flat, d| 3 * flat + d)
}
