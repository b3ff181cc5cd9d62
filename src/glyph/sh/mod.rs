//! Real spherical harmonics of even bands in the conventions of docs/scene-format.md, and the
//! linear maps around them: evaluation, the paper's SH-to-tensor map t = M w
//! (Hlawitschka et al.), basis conversion, rotation and a regularised fit.
//!
//! Conventions (the scene format's contract): coefficient (l, m) of a series up to band
//! L sits at l(l+1)/2 + m for even l = 0, 2, ..., L and m = -l..l; Y_l^m is the complex
//! orthonormal harmonic with the Condon-Shortley phase; `tournier07` and `descoteaux07`
//! (and their `legacy` variants) are real combinations of Y_l^|m| listed in `basis`.
//!
//! Design choices:
//! - Every real basis function is `factor * Q_l^|m|(z) * Re or Im (x + iy)^|m|`, with
//!   Q_l^m = N_l^m P_l^m / sin^m(theta) (`legendre`). Writing the azimuthal part as
//!   (x + iy)^m = sin^m(theta) e^(i m phi) avoids angles altogether: no atan2, no pole
//!   at the z axis, and the same recurrences, run on polynomials instead of numbers,
//!   give M in closed form (`tensor`), since z and x + iy are linear in u.
//! - The four bases differ only in `factor` and in which of Re/Im sits at negative m
//!   (`basis::basis_term`), so conversion between them is a signed, scaled permutation
//!   within each band (`convert`).
//! - Rotation and fitting use least squares on point sets; every band is rotation
//!   invariant, so a rotated series is again a series of the same band and the fit is
//!   exact up to the (small) conditioning of the SH basis on a well-spread point set.
//!   The monomial basis is far worse conditioned, so symmetric tensors are rotated by
//!   exact substitution instead (`crate::glyph::rotate`).
//! - Matrices that depend only on (band, basis, legacy) are built once and shared
//!   through `Arc`s from a process-wide cache (`cache`).
use crate::error::Problem;
use crate::{Error, Result};

mod basis;
mod cache;
mod convert;
mod fit;
mod legendre;
mod names;
mod rotate;
mod tensor;

#[cfg(test)]
mod tests;

pub use crate::glyph::rotate::rotate_symmetric_tensor;
pub use basis::{ShEvaluator, sh_basis_values, sh_eval};
pub use convert::{convert_basis, orthonormal_factors};
pub use fit::ShFitter;
pub(crate) use legendre::{q_table as legendre_table, table_index as legendre_index};
pub use names::{ShBasis, parse_basis, parse_basis_choice};
pub use rotate::rotate_sh;
pub use tensor::{ShToTensor, sh_to_tensor, sh_to_tensor_matrix};

/// Highest band the functions of this module accept. The scene format stops at 12;
/// 16 still keeps the tensor order within `GlyphPolynomial`'s limit of 20 and the
/// u64 multiplicities exact.
pub const MAX_SH_BAND: u32 = 16;

/// Number of coefficients of an even-band SH series up to band L: (L+1)(L+2)/2.
///
/// For an odd L this counts the even bands below it, i.e. it equals `sh_count(L - 1)`,
/// which is what [`sh_basis_values`] returns for that L; the functions that return a
/// `Result` reject odd bands.
pub const fn sh_count(band: u32) -> usize {
    let even = band - band % 2;
    ((even + 1) * (even + 2) / 2) as usize
}

/// Index of (l, m) in the coefficient list: l(l+1)/2 + m (DIPY `sph_harm_ind_list`,
/// MRtrix3 `SH::index`). Meaningful for even l and |m| <= l.
pub(crate) const fn sh_index(l: u32, m: i32) -> usize {
    ((l * (l + 1) / 2) as i64 + m as i64) as usize
}

/// Err unless `band` is even and at most [`MAX_SH_BAND`].
pub fn check_band(band: u32) -> Result<()> {
    if !band.is_multiple_of(2) {
        return Err(Error::data("SH band", Problem::Odd { value: band.into() }));
    }
    if band > MAX_SH_BAND {
        return Err(Error::data(
            "SH band",
            Problem::OutOfRange {
                value: band.into(),
                min: 0.0,
                max: MAX_SH_BAND.into(),
            },
        ));
    }
    Ok(())
}

/// Err unless `band` is valid and `coeffs` has `sh_count(band)` finite entries.
pub(crate) fn check_coefficients(band: u32, coeffs: &[f64]) -> Result<()> {
    check_band(band)?;
    let expected = sh_count(band);
    if coeffs.len() != expected {
        return Err(Error::data(
            "SH coefficients",
            Problem::Count {
                expected,
                found: coeffs.len(),
            },
        ));
    }
    if let Some(i) = coeffs.iter().position(|c| !c.is_finite()) {
        return Err(Error::data(
            "SH coefficients",
            Problem::NotFinite {
                index: i,
                value: coeffs[i],
            },
        ));
    }
    Ok(())
}

/// The even bands 0, 2, ..., band, each with its orders m = -l..l, in coefficient order.
pub fn sh_orders(band: u32) -> impl Iterator<Item = (u32, i32)> {
    (0..=band)
        .step_by(2)
        .flat_map(|l| (-(l as i32)..=l as i32).map(move |m| (l, m)))
}
