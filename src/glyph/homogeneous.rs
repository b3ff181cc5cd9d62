//! Exact algebra on homogeneous polynomials in (x, y, z), stored like
//! [`super::polynomial::GlyphPolynomial`]: monomial coefficients c_k in the order of
//! [`monomials::monomials`]. Products, sums and the factor r^2 = x^2 + y^2 + z^2 are
//! all that the SH-to-tensor construction and the tensor rotation need, so both are
//! done in closed form (float64 rounding of the coefficients only) instead of by
//! fitting, which in the monomial basis would be badly conditioned at high order.
use super::monomials::{self, Monomial};

/// sum_k coeffs[k] x^a_k y^b_k z^c_k over `monomials(degree)`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Homogeneous {
    pub degree: u32,
    pub coeffs: Vec<f64>,
}

impl Homogeneous {
    /// The zero polynomial of the given degree.
    pub fn zero(degree: u32) -> Self {
        Self {
            degree,
            coeffs: vec![0.0; monomials::symmetric_count(degree)],
        }
    }

    /// The constant c (degree 0).
    pub fn constant(c: f64) -> Self {
        Self {
            degree: 0,
            coeffs: vec![c],
        }
    }

    /// The linear form l0 x + l1 y + l2 z (monomial order: x, y, z).
    pub fn linear(l: [f64; 3]) -> Self {
        Self {
            degree: 1,
            coeffs: l.to_vec(),
        }
    }

    /// r^2 = x^2 + y^2 + z^2, which is 1 on the unit sphere.
    pub fn radius_squared() -> Self {
        let mut r2 = Self::zero(2);
        for m in [(2, 0, 0), (0, 2, 0), (0, 0, 2)] {
            r2.add_term(
                Monomial {
                    a: m.0,
                    b: m.1,
                    c: m.2,
                },
                1.0,
            );
        }
        r2
    }

    /// c_k = multiplicity(m_k) t_k: the polynomial of a symmetric tensor (Eq. 5).
    pub fn from_symmetric_tensor(order: u32, tensor: &[f64]) -> Self {
        let coeffs = monomials::monomials(order)
            .into_iter()
            .zip(tensor)
            .map(|(m, t)| monomials::multiplicity(m) as f64 * t)
            .collect();
        Self {
            degree: order,
            coeffs,
        }
    }

    /// t_k = c_k / multiplicity(m_k): the unique symmetric tensor of this polynomial.
    pub fn to_symmetric_tensor(&self) -> Vec<f64> {
        monomials::monomials(self.degree)
            .into_iter()
            .zip(&self.coeffs)
            .map(|(m, c)| c / monomials::multiplicity(m) as f64)
            .collect()
    }

    /// Adds c x^a y^b z^c (the monomial must have this polynomial's degree).
    fn add_term(&mut self, m: Monomial, c: f64) {
        if let Some(slot) = self
            .coeffs
            .get_mut(monomials::monomial_index(self.degree, m))
        {
            *slot += c;
        }
    }

    /// The product self * other, of degree self.degree + other.degree.
    pub fn mul(&self, other: &Self) -> Self {
        let mut out = Self::zero(self.degree + other.degree);
        let other_terms: Vec<_> = monomials::monomials(other.degree)
            .into_iter()
            .zip(&other.coeffs)
            .filter(|(_, c)| **c != 0.0)
            .collect();
        for (m1, c1) in monomials::monomials(self.degree)
            .into_iter()
            .zip(&self.coeffs)
        {
            if *c1 == 0.0 {
                continue;
            }
            for (m2, c2) in &other_terms {
                let m = Monomial {
                    a: m1.a + m2.a,
                    b: m1.b + m2.b,
                    c: m1.c + m2.c,
                };
                out.add_term(m, c1 * *c2);
            }
        }
        out
    }

    /// self^k (k >= 0; self^0 is the constant 1).
    pub fn pow(&self, k: u32) -> Self {
        (0..k).fold(Self::constant(1.0), |acc, _| acc.mul(self))
    }

    /// a self + b other (both of the same degree; a mismatch keeps the shorter list).
    pub fn combine(&self, a: f64, other: &Self, b: f64) -> Self {
        Self {
            degree: self.degree,
            coeffs: self
                .coeffs
                .iter()
                .zip(&other.coeffs)
                .map(|(p, q)| a * p + b * q)
                .collect(),
        }
    }

    /// k self.
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            degree: self.degree,
            coeffs: self.coeffs.iter().map(|c| k * c).collect(),
        }
    }

    /// The same function on the unit sphere as a polynomial of degree self.degree + 2k:
    /// self * (r^2)^k.
    pub fn raised_by(&self, k: u32) -> Self {
        self.mul(&Self::radius_squared().pow(k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::polynomial::GlyphPolynomial;
    use crate::glyph::{Symmetry, TensorLayout};
    use glam::DVec3;

    fn eval(p: &Homogeneous, q: DVec3) -> f64 {
        let poly = GlyphPolynomial {
            order: p.degree,
            coeffs: p.coeffs.clone(),
        };
        poly.eval(q)
    }

    #[test]
    fn products_and_powers_evaluate_as_products() {
        let l = Homogeneous::linear([0.3, -1.2, 0.7]);
        let r2 = Homogeneous::radius_squared();
        let q = DVec3::new(0.4, 1.1, -0.8);
        let lin = 0.3 * q.x - 1.2 * q.y + 0.7 * q.z;
        let p = l.pow(3).mul(&r2);
        assert_eq!(p.degree, 5);
        assert!((eval(&p, q) - lin.powi(3) * q.length_squared()).abs() < 1e-12);
        let sum = p.combine(2.0, &l.raised_by(2), -0.5);
        let want = 2.0 * lin.powi(3) * q.length_squared() - 0.5 * lin * q.length_squared().powi(2);
        assert!((eval(&sum, q) - want).abs() < 1e-12);
    }

    #[test]
    fn symmetric_tensor_round_trip() {
        let t: Vec<f64> = (0..15).map(|i| (i as f64 * 0.37).sin()).collect();
        let p = Homogeneous::from_symmetric_tensor(4, &t);
        let back = p.to_symmetric_tensor();
        t.iter()
            .zip(&back)
            .for_each(|(a, b)| assert!((a - b).abs() < 1e-15));
        let layout = TensorLayout {
            order: 4,
            symmetry: Symmetry::Symmetric,
        };
        let reference = GlyphPolynomial::from_tensor(layout, &t).expect("valid tensor");
        assert_eq!(reference.coeffs, p.coeffs);
    }
}
