//! Rotation of tensor glyphs, the one place for it: the tensor t' with f'(u) = f(R^T u),
//! i.e. t'_(j1..jn) = sum R_(j1 i1) ... R_(jn in) t_(i1..in), for symmetric tensors
//! ([`rotate_symmetric_tensor`]) and full ones ([`rotate_full_tensor`]: non-symmetric
//! glyphs, stiffness tensors). SH series rotate by their own matrices
//! ([`crate::glyph::sh::rotate_sh`]); `volume::reorient` picks the one a glyph kind needs.
//!
//! Instead of contracting the full 3^n tensor n times, the polynomial is rotated by
//! substitution: q_i = (R^T u)_i is the linear form with the coefficients of column i of
//! R, and f(R^T u) = sum_k c_k q_0^a_k q_1^b_k q_2^c_k expands exactly with the powers of
//! the three linear forms (`Homogeneous`). No fit is involved, so nothing depends on the
//! conditioning of the monomial basis.
use glam::DMat3;

use super::homogeneous::Homogeneous;
use super::monomials::{self, symmetric_count};
use crate::error::Problem;
use crate::{Error, Result};

/// Highest order accepted: the u64 multiplicities are exact up to 20.
const MAX_ORDER: u32 = 20;

/// Largest accepted deviation |R^T R - I| (entrywise) of a rotation matrix.
const ORTHOGONALITY_TOLERANCE: f64 = 1e-9;

/// The symmetric tensor (unique coefficients, scene order) of f'(u) = f(R^T u) for
/// R orthogonal (det +1 or -1).
pub fn rotate_symmetric_tensor(order: u32, coeffs: &[f64], r: DMat3) -> Result<Vec<f64>> {
    check_tensor(order, coeffs)?;
    check_orthogonal(r)?;
    let forms: Vec<Vec<Homogeneous>> = (0..3)
        .map(|i| {
            let form = Homogeneous::linear(r.col(i).to_array());
            let mut powers = vec![Homogeneous::constant(1.0)];
            for p in 1..=order as usize {
                let next = powers[p - 1].mul(&form);
                powers.push(next);
            }
            powers
        })
        .collect();
    let f = Homogeneous::from_symmetric_tensor(order, coeffs);
    let mut rotated = Homogeneous::zero(order);
    for (m, c) in monomials::monomials(order).into_iter().zip(&f.coeffs) {
        if *c == 0.0 {
            continue;
        }
        let term = forms[0][m.a as usize]
            .mul(&forms[1][m.b as usize])
            .mul(&forms[2][m.c as usize]);
        rotated = rotated.combine(1.0, &term, *c);
    }
    Ok(rotated.to_symmetric_tensor())
}

fn check_tensor(order: u32, coeffs: &[f64]) -> Result<()> {
    if order > MAX_ORDER {
        return Err(Error::data(
            "symmetric tensor order",
            Problem::OutOfRange {
                value: order.into(),
                min: 0.0,
                max: MAX_ORDER.into(),
            },
        ));
    }
    let expected = symmetric_count(order);
    if coeffs.len() != expected {
        return Err(Error::data(
            "symmetric tensor coefficients",
            Problem::Count {
                expected,
                found: coeffs.len(),
            },
        ));
    }
    if let Some(i) = coeffs.iter().position(|c| !c.is_finite()) {
        return Err(Error::data(
            "tensor coefficients",
            Problem::NotFinite {
                index: i,
                value: coeffs[i],
            },
        ));
    }
    Ok(())
}

/// Err unless R^T R = I to within `ORTHOGONALITY_TOLERANCE` (and R is finite).
pub(crate) fn check_orthogonal(r: DMat3) -> Result<()> {
    let deviation = (r.transpose() * r - DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |acc, v| acc.max(v.abs()));
    // f64::max skips NaN, so non-finite entries are tested on their own.
    if !r.is_finite() || deviation > ORTHOGONALITY_TOLERANCE {
        return Err(Error::data(
            "rotation matrix",
            Problem::NotOrthogonal { deviation },
        ));
    }
    Ok(())
}
/// g(u) = f(R^T u) for a full tensor of order n stored row-major (i1 most significant):
/// `T'[i1..in] = sum over j of R[i1][j1] ... R[in][jn] T[j1..jn]`, applied one index at a
/// time (n passes of 3 multiply-adds per entry instead of 3^n per entry).
pub fn rotate_full_tensor(order: u32, coeffs: &[f64], r: DMat3) -> Result<Vec<f64>> {
    let count = 3usize.pow(order);
    if coeffs.len() != count {
        return Err(Error::data(
            "non-symmetric tensor coefficients",
            Problem::Count {
                expected: count,
                found: coeffs.len(),
            },
        ));
    }
    Ok(turn_each_index(order, coeffs, r))
}

/// [`rotate_full_tensor`] once the length is known to be 3^order.
pub(crate) fn turn_each_index(order: u32, coeffs: &[f64], r: DMat3) -> Vec<f64> {
    let count = coeffs.len();
    // rows[i][j] = R_ij (glam stores columns).
    let rows = [r.row(0), r.row(1), r.row(2)];
    let mut current = coeffs.to_vec();
    let mut next = vec![0.0; count];
    for axis in 0..order {
        let stride = 3usize.pow(order - 1 - axis);
        for (flat, out) in next.iter_mut().enumerate() {
            let i = (flat / stride) % 3;
            let base = flat - i * stride;
            *out = (0..3)
                .map(|j| rows[i][j] * current[base + j * stride])
                .sum();
        }
        std::mem::swap(&mut current, &mut next);
    }
    current
}
