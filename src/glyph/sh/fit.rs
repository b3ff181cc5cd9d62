//! Regularised least-squares SH fit (Descoteaux et al. 2007, "Regularized, fast, and
//! robust analytical Q-ball imaging", MRM 58, Eq. 8 with the Laplace-Beltrami penalty
//! of Eq. 7): w = (B^T B + lambda L)^-1 B^T s with L = diag(l^2 (l+1)^2).
//!
//! The matrix (B^T B + lambda L)^-1 B^T depends only on the directions, so it is built
//! once and each voxel is a matrix-vector product. It is not formed through the normal
//! equations (which square the condition number): it is the first n columns of the
//! pseudo-inverse of the stacked system [B; sqrt(lambda) diag(l(l+1))], whose least
//! squares solution for [s; 0] is the same w, computed by Householder QR. (Not by
//! nalgebra's SVD: in 0.35 it returned factors that reproduce the legacy tournier07
//! basis matrix of band 8 on 165 points only to 4e-7, although that matrix has a
//! condition number of 1.5; cf. nalgebra issue #1172.)
use glam::DVec3;
use nalgebra::DMatrix;

use super::{check_band, sh_basis_values, sh_count, sh_orders};
use crate::error::Problem;
use crate::glyph::sh::ShBasis;
use crate::{Error, Result};

/// Largest accepted condition number (estimate) of the stacked system; above it the
/// directions do not determine the series (too few, or all on a great circle).
const MAX_CONDITION: f64 = 1e10;

/// A fit of SH coefficients to samples on a fixed set of directions.
#[derive(Clone, Debug)]
pub struct ShFitter {
    band: u32,
    basis: ShBasis,
    legacy: bool,
    lambda: f64,
    directions: Vec<DVec3>,
    /// B: one row per direction, one column per coefficient.
    basis_matrix: DMatrix<f64>,
    /// (B^T B + lambda L)^-1 B^T: one row per coefficient.
    solve_matrix: DMatrix<f64>,
}

impl ShFitter {
    /// The fitter for samples at `directions` (normalised here). Err for an invalid
    /// band, a negative or non-finite lambda, a zero or non-finite direction, or
    /// directions that do not determine the coefficients.
    pub fn new(
        band: u32,
        basis: ShBasis,
        legacy: bool,
        directions: &[DVec3],
        lambda: f64,
    ) -> Result<Self> {
        check_band(band)?;
        if !(lambda.is_finite() && lambda >= 0.0) {
            return Err(Error::data(
                "the SH fit's regularisation weight",
                Problem::OutOfRange {
                    value: lambda,
                    min: 0.0,
                    max: f64::INFINITY,
                },
            ));
        }
        let directions = normalised(directions)?;
        let basis_matrix = basis_matrix(band, basis, legacy, &directions);
        let solve_matrix = solve_matrix(band, &basis_matrix, lambda)?;
        Ok(Self {
            band,
            basis,
            legacy,
            lambda,
            directions,
            basis_matrix,
            solve_matrix,
        })
    }

    /// The highest band L of the fitted series.
    pub fn band(&self) -> u32 {
        self.band
    }

    /// The basis of the fitted coefficients, and whether it is the legacy variant.
    pub fn basis(&self) -> (ShBasis, bool) {
        (self.basis, self.legacy)
    }

    /// The weight of the Laplace-Beltrami regularisation (0: plain least squares).
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The directions, normalised, in the order samples are expected.
    pub fn directions(&self) -> &[DVec3] {
        &self.directions
    }

    /// Coefficients fitted to one sample per direction. Samples past the number of
    /// directions are ignored and missing ones count as zero; [`ShFitter::try_fit`]
    /// rejects a wrong count instead.
    pub fn fit(&self, samples: &[f64]) -> Vec<f64> {
        matrix_vector(&self.solve_matrix, samples)
    }

    /// [`ShFitter::fit`], with Err when `samples.len()` is not the number of directions.
    pub fn try_fit(&self, samples: &[f64]) -> Result<Vec<f64>> {
        if samples.len() != self.directions.len() {
            return Err(Error::data(
                "SH fit samples (one per direction)",
                Problem::Count {
                    expected: self.directions.len(),
                    found: samples.len(),
                },
            ));
        }
        Ok(self.fit(samples))
    }

    /// The series with these coefficients at each direction (B w); missing coefficients
    /// count as zero.
    pub fn fitted_values(&self, coeffs: &[f64]) -> Vec<f64> {
        matrix_vector(&self.basis_matrix, coeffs)
    }
}

fn normalised(directions: &[DVec3]) -> Result<Vec<DVec3>> {
    directions
        .iter()
        .enumerate()
        .map(|(i, d)| {
            d.try_normalize()
                .ok_or_else(|| Error::data("SH fit directions", Problem::ZeroVector { index: i }))
        })
        .collect()
}

fn basis_matrix(band: u32, basis: ShBasis, legacy: bool, directions: &[DVec3]) -> DMatrix<f64> {
    let rows: Vec<f64> = directions
        .iter()
        .flat_map(|u| sh_basis_values(band, basis, legacy, *u))
        .collect();
    DMatrix::from_row_slice(directions.len(), sh_count(band), &rows)
}

/// First n columns of pinv([B; sqrt(lambda) diag(l(l+1))]) = R^-1 Q^T from a Householder
/// QR of the stacked matrix.
fn solve_matrix(band: u32, b: &DMatrix<f64>, lambda: f64) -> Result<DMatrix<f64>> {
    let (n, cols) = b.shape();
    let mut stacked = DMatrix::zeros(n + cols, cols);
    stacked.rows_mut(0, n).copy_from(b);
    for (j, (l, _)) in sh_orders(band).enumerate() {
        stacked[(n + j, j)] = lambda.sqrt() * f64::from(l * (l + 1));
    }
    let qr = stacked.qr();
    let r = qr.r();
    let undetermined = |condition: f64| {
        Error::data(
            "SH fit directions",
            Problem::IllConditioned {
                known: n,
                unknowns: cols,
                condition,
            },
        )
    };
    let r_inverse = r
        .solve_upper_triangular(&DMatrix::identity(cols, cols))
        .ok_or_else(|| undetermined(f64::INFINITY))?;
    // Frobenius condition number: at least the 2-norm one, at most `cols` times it.
    let condition = r.norm() * r_inverse.norm();
    if condition.is_nan() || condition >= MAX_CONDITION {
        return Err(undetermined(condition));
    }
    Ok(r_inverse * qr.q().rows(0, n).transpose())
}

fn matrix_vector(m: &DMatrix<f64>, v: &[f64]) -> Vec<f64> {
    m.row_iter()
        .map(|row| row.iter().zip(v).map(|(a, b)| a * b).sum())
        .collect()
}
