//! Least-squares fit of a symmetric tensor of even order n to apparent diffusion
//! coefficients: generalised DTI (Özarslan and Mareci, "Generalized diffusion tensor
//! imaging and analytical relationships between diffusion tensor imaging and high angular
//! resolution diffusion imaging", MRM 50, 2003).
//!
//! The Stejskal-Tanner relation S_i = S0 exp(-b_i D(g_i)) with the diffusivity profile
//! D(g) = sum_k m_k t_k gx^a_k gy^b_k gz^c_k (the generalised tensor's diffusivity, with
//! the unique coefficients t_k in the scene format's order and m_k the multiplicities of
//! `glyph::monomials`) is linear in t: with ADC_i = -ln(S_i / S0) / b_i, minimise
//! sum_i (D(g_i) - ADC_i)^2, i.e. min |A t - adc|^2 with A_ik = m_k g_i^(a_k, b_k, c_k).
//! (Unweighted least squares on the ADCs; a weighted fit, as in Salvador et al. 2005,
//! would need a solve per voxel.)
//!
//! A depends only on the directions, so its pseudo-inverse A+ (from the SVD) is formed
//! once and each voxel costs one matrix-vector product. The SVD also gives the rank:
//! a set of directions that cannot separate the (n+1)(n+2)/2 unknowns (too few, or
//! too many of them on one great circle) is refused instead of fitted to noise.
use glam::DVec3;
use nalgebra::DMatrix;

use glyphcast::error::Problem;
use glyphcast::glyph::monomials::{monomials, multiplicity, symmetric_count};
use glyphcast::{Error, Result, Setting};

/// Singular values below this fraction of the largest count as zero.
const RANK_TOLERANCE: f64 = 1e-10;

/// Design matrix and pseudo-inverse for one set of gradient directions.
#[derive(Clone, Debug)]
pub struct TensorFitter {
    order: u32,
    /// A, directions x coefficients.
    design: DMatrix<f64>,
    /// A+, coefficients x directions.
    pseudo_inverse: DMatrix<f64>,
}

/// Row i of A: m_k g^(a_k, b_k, c_k) for every monomial k of `order`.
pub fn design_row(order: u32, g: DVec3) -> Vec<f64> {
    monomials(order)
        .into_iter()
        .map(|m| {
            let power = g.x.powi(m.a as i32) * g.y.powi(m.b as i32) * g.z.powi(m.c as i32);
            multiplicity(m) as f64 * power
        })
        .collect()
}

/// A: one [`design_row`] per direction.
fn design_matrix(order: u32, directions: &[DVec3]) -> DMatrix<f64> {
    let rows: Vec<f64> = directions
        .iter()
        .flat_map(|&g| design_row(order, g))
        .collect();
    DMatrix::from_row_slice(directions.len(), symmetric_count(order), &rows)
}

/// How many of the (n+1)(n+2)/2 coefficients of an order-n tensor the directions
/// determine: the numerical rank of the design matrix. It is also the number of even
/// SH up to band n that they determine, as both span the homogeneous polynomials of
/// degree n restricted to the sphere.
pub fn design_rank(order: u32, directions: &[DVec3]) -> usize {
    let svd = design_matrix(order, directions).svd(false, false);
    svd.rank(RANK_TOLERANCE * svd.singular_values.max())
}

impl TensorFitter {
    /// Err([`Error::Setting`]) for an odd or zero order; [`Error::Data`] for, fewer directions than
    /// unknowns, or directions that leave the design rank-deficient.
    pub fn new(order: u32, directions: &[DVec3]) -> Result<Self> {
        if order == 0 || order % 2 == 1 {
            return Err(Error::setting_value(
                Setting::Order,
                order,
                "the diffusion profile is antipodally symmetric, the order must be even and at \
                 least 2",
            ));
        }
        let unknowns = symmetric_count(order);
        if directions.len() < unknowns {
            return Err(Error::data(
                "diffusion-weighted directions",
                Problem::Underdetermined {
                    known: directions.len(),
                    unknowns,
                },
            ));
        }
        let design = design_matrix(order, directions);
        let svd = design.clone().svd(true, true);
        let eps = RANK_TOLERANCE * svd.singular_values.max();
        let rank = svd.rank(eps);
        if rank < unknowns {
            return Err(Error::data(
                "diffusion-weighted directions",
                Problem::RankDeficient { rank, unknowns },
            ));
        }
        let pseudo_inverse = svd.pseudo_inverse(eps).map_err(|e| Error::Numerical {
            step: "the tensor fit's pseudo-inverse",
            detail: e.to_string(),
        })?;
        Ok(Self {
            order,
            design,
            pseudo_inverse,
        })
    }

    /// The tensor's order (even).
    pub fn order(&self) -> u32 {
        self.order
    }

    /// Number of unique coefficients, (n+1)(n+2)/2.
    pub fn coefficient_count(&self) -> usize {
        self.pseudo_inverse.nrows()
    }

    /// t = A+ adc, written into `coeffs` (length `coefficient_count`); `adc` has one
    /// value per direction, in the order given to `new`.
    pub fn fit_into(&self, adc: &[f64], coeffs: &mut [f64]) {
        for (k, c) in coeffs.iter_mut().enumerate() {
            *c = self
                .pseudo_inverse
                .row(k)
                .iter()
                .zip(adc)
                .map(|(p, a)| p * a)
                .sum();
        }
    }

    /// The fitted profile D(g_i) at the fitter's directions.
    pub fn fitted_values(&self, coeffs: &[f64]) -> Vec<f64> {
        (0..self.design.nrows())
            .map(|i| {
                self.design
                    .row(i)
                    .iter()
                    .zip(coeffs)
                    .map(|(a, t)| a * t)
                    .sum()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glyphcast::glyph::polynomial::GlyphPolynomial;
    use glyphcast::glyph::{Symmetry, TensorLayout};
    use glyphcast::rng::SplitMix64;

    fn directions(count: usize, seed: u64) -> Vec<DVec3> {
        let mut rng = SplitMix64::new(seed);
        (0..count).map(|_| rng.direction()).collect()
    }

    #[test]
    fn recovers_a_tensor_from_its_exact_profile() {
        for order in [2, 4, 6, 8] {
            let dirs = directions(120, order as u64);
            let mut rng = SplitMix64::new(10 + order as u64);
            let truth: Vec<f64> = (0..symmetric_count(order))
                .map(|_| 2.0 * rng.unit() - 1.0)
                .collect();
            let layout = TensorLayout {
                order,
                symmetry: Symmetry::Symmetric,
            };
            let f = GlyphPolynomial::from_tensor(layout, &truth).unwrap();
            let adc: Vec<f64> = dirs.iter().map(|&g| f.eval(g)).collect();
            let fitter = TensorFitter::new(order, &dirs).unwrap();
            let mut fitted = vec![0.0; fitter.coefficient_count()];
            fitter.fit_into(&adc, &mut fitted);
            for (a, b) in fitted.iter().zip(&truth) {
                assert!((a - b).abs() < 1e-9, "order {order}: {a} vs {b}");
            }
            for (a, b) in fitter.fitted_values(&fitted).iter().zip(&adc) {
                assert!((a - b).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn refuses_odd_orders_too_few_and_degenerate_directions() {
        assert!(TensorFitter::new(3, &directions(30, 1)).is_err());
        let err = TensorFitter::new(4, &directions(14, 1)).unwrap_err();
        assert!(
            matches!(
                err,
                Error::Data {
                    problem: Problem::Underdetermined {
                        known: 14,
                        unknowns: 15
                    },
                    ..
                }
            ),
            "{err}"
        );
        assert!(
            err.to_string()
                .starts_with("diffusion-weighted directions: 14 "),
            "{err}"
        );
        // All directions on the equator: z-terms are undetermined.
        let equator: Vec<DVec3> = (0..40)
            .map(|i| {
                let a = i as f64 * 0.3;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let err = TensorFitter::new(2, &equator).unwrap_err();
        assert!(err.to_string().contains("determine only"), "{err}");
    }
}
