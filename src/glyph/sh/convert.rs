//! Conversion between the SH bases of the scene format.
//!
//! Every basis function is factor * Q_l^|m| * part((x+iy)^|m|) (`basis::basis_term`),
//! so the coefficient of a basis function on one side is the coefficient of the
//! function with the same l, |m| and part on the other, times factor_from / factor_to:
//! a signed, scaled permutation within each band, exact up to one rounding per entry.
use super::basis::{basis_term, signed_order};
use super::{check_coefficients, sh_index, sh_orders};
use crate::Result;
use crate::glyph::sh::ShBasis;

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

/// Per coefficient of `band` in basis (basis, legacy), the factor that makes it the
/// coefficient of the orthonormal basis function with the same l, |m| and part, up to
/// its sign: 1 for m = 0 and for the sqrt2 variants, 1/sqrt2 for an m != 0 term of
/// legacy tournier07 (the one variant without the sqrt2).
/// The sum of squares of the scaled coefficients is then the series' mean square over
/// the sphere times 4 pi (Parseval), whatever the basis.
pub fn orthonormal_factors(band: u32, basis: ShBasis, legacy: bool) -> Vec<f64> {
    sh_orders(band)
        .map(|(_, m)| {
            let (_, factor) = basis_term(basis, legacy, m);
            if m == 0 {
                1.0
            } else {
                factor.abs() / std::f64::consts::SQRT_2
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Scaled by the factors, every basis's coefficients are those of the orthonormal
    /// tournier07 series up to sign.
    #[test]
    fn orthonormal_factors_match_the_conversion_to_an_orthonormal_basis() {
        let band = 6;
        let coeffs: Vec<f64> = (0..28).map(|j| 0.3 + (j as f64 * 0.77).sin()).collect();
        for basis in [ShBasis::Tournier07, ShBasis::Descoteaux07] {
            for legacy in [false, true] {
                let factors = orthonormal_factors(band, basis, legacy);
                let orthonormal =
                    convert_basis(band, (basis, legacy), (ShBasis::Tournier07, false), &coeffs)
                        .expect("converted");
                let power: f64 = coeffs
                    .iter()
                    .zip(&factors)
                    .map(|(c, f)| (c * f).powi(2))
                    .sum();
                let expected: f64 = orthonormal.iter().map(|c| c * c).sum();
                assert!(
                    (power - expected).abs() < 1e-12 * expected,
                    "{basis:?} {legacy}"
                );
                // Only tournier07's legacy variant drops the sqrt2 (descoteaux07's changes
                // phases only).
                if legacy && basis == ShBasis::Tournier07 {
                    assert!(factors.iter().any(|&f| (f - 0.5f64.sqrt()).abs() < 1e-15));
                } else {
                    assert!(factors.iter().all(|&f| f == 1.0));
                }
            }
        }
    }
}
