//! Conversion between the SH bases of the scene format.
//!
//! Every basis function is factor * Q_l^|m| * part((x+iy)^|m|) (`basis::basis_term`),
//! so the coefficient of a basis function on one side is the coefficient of the
//! function with the same l, |m| and part on the other, times factor_from / factor_to:
//! a signed, scaled permutation within each band, exact up to one rounding per entry.
use super::basis::{basis_term, signed_order};
use super::{check_coefficients, sh_index, sh_orders};
use crate::Result;
use crate::scene::ShBasis;

/// The coefficients in basis `to` (basis, legacy) of the series given in `from`.
pub fn convert_basis(
    band: u32,
    from: (ShBasis, bool),
    to: (ShBasis, bool),
    coeffs: &[f64],
) -> Result<Vec<f64>> {
    check_coefficients(band, coeffs)?;
    let mut out = vec![0.0; coeffs.len()];
    for ((l, m), w) in sh_orders(band).zip(coeffs) {
        let (part, factor_from) = basis_term(from.0, from.1, m);
        let m_to = signed_order(to.0, m.unsigned_abs(), part);
        let (_, factor_to) = basis_term(to.0, to.1, m_to);
        if let Some(slot) = out.get_mut(sh_index(l, m_to)) {
            *slot = w * factor_from / factor_to;
        }
    }
    Ok(out)
}
