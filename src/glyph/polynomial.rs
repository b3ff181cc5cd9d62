//! A glyph function f(q) as a homogeneous polynomial of degree n in q = (x, y, z), stored
//! by its monomial coefficients c_k in the order of [`monomials::monomials`]:
//! f(q) = sum_k c_k x^a_k y^b_k z^c_k (scene format, "The glyph surface").
//!
//! Both tensor layouts reduce to this one form, so everything downstream (bounds, the ray
//! intersection, the GPU coefficient buffers) sees a single representation:
//! - symmetric (the paper's Eq. 5): c_k = multiplicity(m_k) * t_k;
//! - non-symmetric (Eq. 4): c_k = sum of the entries T[i1..in] whose index multiset is
//!   monomial k.
//!
//! Evaluation uses a nested Horner scheme that follows the coefficient order directly:
//! f = sum_a x^a P_a(y, z) with a running from n down to 0 is Horner in x, and each
//! P_a(y, z) = sum_b c_(a,b) y^b z^(n-a-b) with b descending is Horner in y where the
//! z power grows by one factor per step. No power tables and no allocation, which matters
//! because the bounds evaluate f thousands of times per glyph. [`GlyphPolynomial::along_line`]
//! runs the same scheme with univariate polynomials in t in place of numbers.
use std::sync::OnceLock;

use glam::DVec3;

use super::monomials;
use super::{Symmetry, TensorLayout};
use crate::error::Problem;
use crate::{Error, Result};

/// Highest order accepted by [`GlyphPolynomial::from_tensor`]: the multiplicities
/// n!/(a! b! c!) of `monomials::multiplicity` are computed with u64 factorials, which
/// overflow above 20! (the scene format itself stops at 12).
const MAX_ORDER: u32 = 20;

/// f(q) = `sum_k coeffs[k] x^a_k y^b_k z^c_k` over `monomials(order)`.
#[derive(Clone, Debug, PartialEq)]
pub struct GlyphPolynomial {
    /// The degree n.
    pub order: u32,
    /// One per monomial, in the order of `monomials(order)`.
    pub coeffs: Vec<f64>,
}

impl GlyphPolynomial {
    /// Monomial coefficients of a tensor in the scene format's layout.
    ///
    /// Err([`Error::Data`]) if the order is 0 or above 20, if `tensor.len()` is not
    /// `layout.coefficient_count()`, or if an entry is not finite.
    pub fn from_tensor(layout: TensorLayout, tensor: &[f64]) -> Result<Self> {
        let order = layout.order;
        if order == 0 || order > MAX_ORDER {
            return Err(Error::data(
                "tensor order",
                Problem::OutOfRange {
                    value: order.into(),
                    min: 1.0,
                    max: MAX_ORDER.into(),
                },
            ));
        }
        let expected = layout.coefficient_count();
        if tensor.len() != expected {
            return Err(Error::data(
                "tensor coefficients",
                Problem::Count {
                    expected,
                    found: tensor.len(),
                },
            ));
        }
        if let Some(i) = tensor.iter().position(|v| !v.is_finite()) {
            return Err(Error::data(
                "tensor coefficients",
                Problem::NotFinite {
                    index: i,
                    value: tensor[i],
                },
            ));
        }
        let coeffs = match layout.symmetry {
            Symmetry::Symmetric => symmetric_coefficients(order, tensor),
            Symmetry::NonSymmetric => nonsymmetric_coefficients(order, tensor),
        };
        Ok(Self { order, coeffs })
    }

    /// f(q).
    pub fn eval(&self, q: DVec3) -> f64 {
        horner3(self.order, self.coefficients(), q)
    }

    /// f(q) and its gradient, by differentiating the nested Horner recurrences.
    pub fn eval_with_gradient(&self, q: DVec3) -> (f64, DVec3) {
        let mut coeffs = self.coefficients();
        let (mut f, mut fx, mut fy, mut fz) = (0.0, 0.0, 0.0, 0.0);
        for a in (0..=self.order).rev() {
            let (p, py, pz) = yz_part_with_gradient(self.order - a, &mut coeffs, q.y, q.z);
            fx = fx * q.x + f;
            f = f * q.x + p;
            fy = fy * q.x + py;
            fz = fz * q.x + pz;
        }
        (f, DVec3::new(fx, fy, fz))
    }

    /// sum_k |c_k| |monomial_k(q)|: the scale that float rounding errors of `eval` are
    /// relative to (and an upper bound of |f(q)|).
    pub fn abs_eval(&self, q: DVec3) -> f64 {
        horner3(self.order, self.coefficients().map(f64::abs), q.abs())
    }

    /// sum_k |c_k|, an upper bound of |f| on the unit ball (every monomial is <= 1 there).
    pub fn abs_coefficient_sum(&self) -> f64 {
        self.coeffs.iter().map(|c| c.abs()).sum()
    }

    /// The polynomial k f.
    pub fn scaled(&self, k: f64) -> Self {
        Self {
            order: self.order,
            coeffs: self.coeffs.iter().map(|c| k * c).collect(),
        }
    }

    /// Coefficients (ascending powers of t) of f(a + t b), degree `order`.
    pub fn along_line(&self, a: DVec3, b: DVec3) -> Vec<f64> {
        let len = self.order as usize + 1;
        let z_powers = linear_powers(a.z, b.z, len);
        let mut coeffs = self.coefficients();
        let mut f = vec![0.0; len];
        let mut p = vec![0.0; len];
        for a_pow in (0..=self.order).rev() {
            p.iter_mut().for_each(|v| *v = 0.0);
            for zp in z_powers.iter().take((self.order - a_pow) as usize + 1) {
                let c = coeffs.next().unwrap_or(0.0);
                univariate::mul_linear_in_place(&mut p, a.y, b.y);
                p.iter_mut().zip(zp).for_each(|(v, z)| *v += c * z);
            }
            univariate::mul_linear_in_place(&mut f, a.x, b.x);
            f.iter_mut().zip(&p).for_each(|(v, pv)| *v += pv);
        }
        f
    }

    /// The coefficients followed by zeros, so that a hand-built polynomial whose `coeffs`
    /// is too short evaluates as if padded instead of panicking.
    /// The coefficients in monomial order (x powers descending, then y powers
    /// descending), the order of `monomial_values`.
    pub fn monomial_coefficients(&self) -> &[f64] {
        &self.coeffs
    }

    fn coefficients(&self) -> impl Iterator<Item = f64> + '_ {
        self.coeffs.iter().copied().chain(std::iter::repeat(0.0))
    }
}

/// The entries of the symmetric tensor of order n + 2k whose polynomial is
/// f(q) (q . q)^k, from the entries `tensor` of a symmetric tensor of order n: the same
/// glyph, since |f(q)| (q . q)^k = |q|^(n + 2k + 1) holds exactly where
/// |f(q)| = |q|^(n + 1) does (q != 0), with the same sign of f and the same surface
/// normal there. A one-shot render draws small sets of lower orders this way with the
/// pipeline of a higher one (`render::promote`).
pub(crate) fn raised_symmetric_tensor(order: u32, tensor: &[f64], k: u32) -> Vec<f64> {
    let mut poly: Vec<f64> = symmetric_coefficients(order, tensor);
    let mut degree = order;
    for _ in 0..k {
        // Times x^2 + y^2 + z^2: each monomial (a, b, c) feeds (a + 2, b, c),
        // (a, b + 2, c) and (a, b, c + 2).
        let mut next = vec![0.0; monomials::symmetric_count(degree + 2)];
        for (m, c) in monomials::monomials(degree).into_iter().zip(&poly) {
            for (da, db, dc) in [(2, 0, 0), (0, 2, 0), (0, 0, 2)] {
                let raised = monomials::Monomial {
                    a: m.a + da,
                    b: m.b + db,
                    c: m.c + dc,
                };
                next[monomials::monomial_index(degree + 2, raised)] += c;
            }
        }
        poly = next;
        degree += 2;
    }
    monomials::monomials(degree)
        .into_iter()
        .zip(poly)
        .map(|(m, c)| c / monomials::multiplicity(m) as f64)
        .collect()
}

/// c_k = multiplicity(m_k) t_k (Eq. 5 weights).
fn symmetric_coefficients(order: u32, tensor: &[f64]) -> Vec<f64> {
    multiplicities(order)
        .iter()
        .zip(tensor)
        .map(|(w, t)| w * t)
        .collect()
}

/// The multiplicities of `monomials(order)` as float64, computed once per order (a
/// million glyphs would otherwise list the monomials and divide factorials each time).
/// `order` is at most [`MAX_ORDER`]; a higher one gets an empty list.
fn multiplicities(order: u32) -> &'static [f64] {
    static TABLES: [OnceLock<Vec<f64>>; MAX_ORDER as usize + 1] =
        [const { OnceLock::new() }; MAX_ORDER as usize + 1];
    TABLES.get(order as usize).map_or(&[], |table| {
        table.get_or_init(|| {
            monomials::monomials(order)
                .into_iter()
                .map(|m| monomials::multiplicity(m) as f64)
                .collect()
        })
    })
}

/// c_k = sum of the entries whose index multiset is monomial k (Eq. 4 collected).
fn nonsymmetric_coefficients(order: u32, tensor: &[f64]) -> Vec<f64> {
    let mut coeffs = vec![0.0; monomials::symmetric_count(order)];
    for (flat, t) in tensor.iter().enumerate() {
        let m = monomials::nonsymmetric_entry_monomial(order, flat);
        coeffs[monomials::monomial_index(order, m)] += t;
    }
    coeffs
}

/// The value of every monomial of degree `order` at q, in the coefficients' order: f(q)
/// is the dot product of these with [`GlyphPolynomial::monomial_coefficients`].
pub(crate) fn monomial_values(order: u32, q: DVec3) -> impl Iterator<Item = f64> {
    (0..=order).rev().flat_map(move |a| {
        let m = order - a;
        (0..=m)
            .rev()
            .map(move |b| q.x.powi(a as i32) * q.y.powi(b as i32) * q.z.powi((m - b) as i32))
    })
}

/// Nested Horner evaluation of sum_k c_k x^a y^b z^c in monomial order.
fn horner3(order: u32, mut coeffs: impl Iterator<Item = f64>, q: DVec3) -> f64 {
    let mut f = 0.0;
    for a in (0..=order).rev() {
        f = f * q.x + yz_part(order - a, &mut coeffs, q.y, q.z);
    }
    f
}

/// P(y, z) = sum_b c_b y^b z^(m-b) for b = m down to 0, taking m + 1 coefficients.
fn yz_part(m: u32, coeffs: &mut impl Iterator<Item = f64>, y: f64, z: f64) -> f64 {
    let (mut p, mut zp) = (0.0, 1.0);
    for _ in 0..=m {
        p = p * y + coeffs.next().unwrap_or(0.0) * zp;
        zp *= z;
    }
    p
}

/// `yz_part` and its partial derivatives in y and z.
fn yz_part_with_gradient(
    m: u32,
    coeffs: &mut impl Iterator<Item = f64>,
    y: f64,
    z: f64,
) -> (f64, f64, f64) {
    let (mut p, mut py, mut pz) = (0.0, 0.0, 0.0);
    let (mut zp, mut zp_z) = (1.0, 0.0);
    for _ in 0..=m {
        let c = coeffs.next().unwrap_or(0.0);
        py = py * y + p;
        pz = pz * y + c * zp_z;
        p = p * y + c * zp;
        zp_z = zp_z * z + zp;
        zp *= z;
    }
    (p, py, pz)
}

/// (c0 + c1 t)^k for k = 0..len, each padded to `len` coefficients.
fn linear_powers(c0: f64, c1: f64, len: usize) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(len);
    let mut power = vec![0.0; len];
    if let Some(first) = power.first_mut() {
        *first = 1.0;
    }
    for _ in 0..len {
        out.push(power.clone());
        univariate::mul_linear_in_place(&mut power, c0, c1);
    }
    out
}

/// Real polynomials in one variable, coefficients in ascending powers.
pub(crate) mod univariate {
    /// p(t) by Horner's rule.
    pub(crate) fn eval(p: &[f64], t: f64) -> f64 {
        p.iter().rev().fold(0.0, |acc, c| acc * t + c)
    }

    /// p(t) and p'(t) by Horner's rule.
    pub(crate) fn eval_with_derivative(p: &[f64], t: f64) -> (f64, f64) {
        p.iter()
            .rev()
            .fold((0.0, 0.0), |(v, d), c| (v * t + c, d * t + v))
    }

    /// sum_i |p_i| |t|^i: the scale of Horner's rounding error at t (Higham, Eq. 5.3:
    /// |computed - exact| <= gamma_2d times this).
    pub(crate) fn abs_eval(p: &[f64], t: f64) -> f64 {
        let at = t.abs();
        p.iter().rev().fold(0.0, |acc, c| acc * at + c.abs())
    }

    /// p'.
    pub(crate) fn derivative(p: &[f64]) -> Vec<f64> {
        p.iter()
            .enumerate()
            .skip(1)
            .map(|(i, c)| i as f64 * c)
            .collect()
    }

    /// p q.
    pub(crate) fn multiply(p: &[f64], q: &[f64]) -> Vec<f64> {
        if p.is_empty() || q.is_empty() {
            return Vec::new();
        }
        let mut out = vec![0.0; p.len() + q.len() - 1];
        for (i, a) in p.iter().enumerate() {
            for (j, b) in q.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        out
    }

    /// p^k (p^0 = 1).
    pub(crate) fn power(p: &[f64], k: u32) -> Vec<f64> {
        (0..k).fold(vec![1.0], |acc, _| multiply(&acc, p))
    }

    /// p <- p (c0 + c1 t), keeping the length: the top coefficient of p must be zero.
    pub(crate) fn mul_linear_in_place(p: &mut [f64], c0: f64, c1: f64) {
        for i in (1..p.len()).rev() {
            p[i] = p[i] * c0 + p[i - 1] * c1;
        }
        if let Some(first) = p.first_mut() {
            *first *= c0;
        }
    }

    /// p without its trailing (highest-power) exact zeros.
    pub(crate) fn trimmed(p: &[f64]) -> &[f64] {
        let len = p.iter().rposition(|c| *c != 0.0).map_or(0, |i| i + 1);
        &p[..len]
    }
}

/// Deterministic random numbers and tensors shared by the glyph tests (no extra
/// dependency: SplitMix64 is enough for test inputs).
#[cfg(test)]
pub(crate) mod test_support {
    use glam::DVec3;

    pub(crate) struct Rng(crate::rng::SplitMix64);

    impl Rng {
        pub(crate) fn new(seed: u64) -> Self {
            Self(crate::rng::SplitMix64::new(seed))
        }

        /// Uniform in [lo, hi).
        pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.0.unit()
        }

        pub(crate) fn vector(&mut self, lo: f64, hi: f64) -> DVec3 {
            DVec3::new(
                self.uniform(lo, hi),
                self.uniform(lo, hi),
                self.uniform(lo, hi),
            )
        }

        pub(crate) fn unit_vector(&mut self) -> DVec3 {
            loop {
                let v = self.vector(-1.0, 1.0);
                let len = v.length();
                if len > 1e-3 && len <= 1.0 {
                    return v / len;
                }
            }
        }

        pub(crate) fn values(&mut self, count: usize, lo: f64, hi: f64) -> Vec<f64> {
            (0..count).map(|_| self.uniform(lo, hi)).collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::Rng;
    use super::*;
    use crate::glyph::monomials::{Monomial, monomial_index, symmetric_count};

    fn layout(order: u32, symmetry: Symmetry) -> TensorLayout {
        TensorLayout { order, symmetry }
    }

    fn symmetric(order: u32, t: &[f64]) -> GlyphPolynomial {
        GlyphPolynomial::from_tensor(layout(order, Symmetry::Symmetric), t).unwrap()
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn raised_tensor_is_f_times_a_power_of_q_dot_q() {
        let mut rng = Rng::new(0x7a15ed);
        for order in 1..=10 {
            for k in 1..=3 {
                let t = rng.values(symmetric_count(order), -1.0, 1.0);
                let raised = raised_symmetric_tensor(order, &t, k);
                assert_eq!(raised.len(), symmetric_count(order + 2 * k));
                let (f, g) = (symmetric(order, &t), symmetric(order + 2 * k, &raised));
                for _ in 0..20 {
                    let q = rng.vector(-1.5, 1.5);
                    let want = f.eval(q) * q.length_squared().powi(k as i32);
                    let scale =
                        f.abs_coefficient_sum() * q.length().max(1.0).powi((order + 2 * k) as i32);
                    assert!(
                        close(g.eval(q), want, 1e-13 * scale),
                        "order {order}, k {k}: {} against {want}",
                        g.eval(q)
                    );
                }
            }
        }
    }

    /// The index tuple of flat entry `flat` of a non-symmetric tensor, i1 first.
    fn index_tuple(order: u32, flat: usize) -> Vec<usize> {
        let mut out = vec![0; order as usize];
        let mut rest = flat;
        for slot in out.iter_mut().rev() {
            *slot = rest % 3;
            rest /= 3;
        }
        out
    }

    /// sum over all 3^n tuples of T[i1..in] u_i1 ... u_in, straight from Eq. 4.
    fn brute_force_full(order: u32, full: &[f64], q: DVec3) -> f64 {
        let u = q.to_array();
        full.iter()
            .enumerate()
            .map(|(flat, t)| {
                t * index_tuple(order, flat)
                    .iter()
                    .map(|&i| u[i])
                    .product::<f64>()
            })
            .sum()
    }

    /// The full 3^n tensor of a symmetric tensor given by its unique entries.
    fn expand_symmetric(order: u32, unique: &[f64]) -> Vec<f64> {
        (0..3usize.pow(order))
            .map(|flat| {
                let tuple = index_tuple(order, flat);
                let count = |i| tuple.iter().filter(|&&v| v == i).count() as u32;
                let m = Monomial {
                    a: count(0),
                    b: count(1),
                    c: count(2),
                };
                unique[monomial_index(order, m)]
            })
            .collect()
    }

    fn permutations(n: usize) -> Vec<Vec<usize>> {
        if n == 0 {
            return vec![Vec::new()];
        }
        let mut out = Vec::new();
        for p in permutations(n - 1) {
            for pos in 0..=p.len() {
                let mut q = p.clone();
                q.insert(pos, n - 1);
                out.push(q);
            }
        }
        out
    }

    fn flat_index(tuple: &[usize]) -> usize {
        tuple.iter().fold(0, |acc, i| acc * 3 + i)
    }

    /// Unique entries of the symmetrisation (1/n!) sum_sigma T[sigma(i)], each taken at
    /// its sorted index tuple.
    fn symmetrised_unique(order: u32, full: &[f64]) -> Vec<f64> {
        let perms = permutations(order as usize);
        let mut unique = vec![0.0; symmetric_count(order)];
        for flat in 0..full.len() {
            let tuple = index_tuple(order, flat);
            if tuple.windows(2).any(|w| w[0] > w[1]) {
                continue;
            }
            let sum: f64 = perms
                .iter()
                .map(|p| full[flat_index(&p.iter().map(|&k| tuple[k]).collect::<Vec<_>>())])
                .sum();
            let m = monomials::nonsymmetric_entry_monomial(order, flat);
            unique[monomial_index(order, m)] = sum / perms.len() as f64;
        }
        unique
    }

    #[test]
    fn identity_order_two_is_squared_length() {
        let f = symmetric(2, &[1.0, 0.0, 0.0, 1.0, 0.0, 1.0]);
        assert_eq!(f.coeffs, vec![1.0, 0.0, 0.0, 1.0, 0.0, 1.0]);
        let mut rng = Rng::new(1);
        for _ in 0..20 {
            let q = rng.vector(-2.0, 2.0);
            assert!(close(f.eval(q), q.length_squared(), 1e-14));
        }
    }

    #[test]
    fn symmetric_multiplicities_follow_eq5() {
        // Order 2: xx, xy, xz, yy, yz, zz with weights 1, 2, 2, 1, 2, 1.
        let f = symmetric(2, &[1.0; 6]);
        assert_eq!(f.coeffs, vec![1.0, 2.0, 2.0, 1.0, 2.0, 1.0]);
    }

    #[test]
    fn rejects_bad_lengths_orders_and_values() {
        let sym = layout(4, Symmetry::Symmetric);
        assert!(GlyphPolynomial::from_tensor(sym, &[0.0; 14]).is_err());
        assert!(GlyphPolynomial::from_tensor(sym, &[0.0; 15]).is_ok());
        let non = layout(2, Symmetry::NonSymmetric);
        assert!(GlyphPolynomial::from_tensor(non, &[0.0; 6]).is_err());
        assert!(GlyphPolynomial::from_tensor(layout(0, Symmetry::Symmetric), &[1.0]).is_err());
        assert!(GlyphPolynomial::from_tensor(layout(21, Symmetry::Symmetric), &[]).is_err());
        let mut bad = [0.0; 6];
        bad[3] = f64::NAN;
        assert!(GlyphPolynomial::from_tensor(layout(2, Symmetry::Symmetric), &bad).is_err());
    }

    #[test]
    fn nonsymmetric_matches_its_symmetrisation() {
        let mut rng = Rng::new(2);
        for order in 1..=5 {
            let full = rng.values(3usize.pow(order), -1.0, 1.0);
            let non =
                GlyphPolynomial::from_tensor(layout(order, Symmetry::NonSymmetric), &full).unwrap();
            let sym = symmetric(order, &symmetrised_unique(order, &full));
            for _ in 0..10 {
                let q = rng.vector(-1.0, 1.0);
                assert!(close(non.eval(q), sym.eval(q), 1e-12), "order {order}");
            }
        }
    }

    #[test]
    fn nonsymmetric_matches_brute_force_eq4() {
        let mut rng = Rng::new(3);
        for order in 1..=4 {
            let full = rng.values(3usize.pow(order), -1.0, 1.0);
            let f =
                GlyphPolynomial::from_tensor(layout(order, Symmetry::NonSymmetric), &full).unwrap();
            for _ in 0..10 {
                let q = rng.vector(-1.2, 1.2);
                let want = brute_force_full(order, &full, q);
                assert!(close(f.eval(q), want, 1e-12), "order {order}");
            }
        }
    }

    #[test]
    fn symmetric_matches_brute_force_of_expanded_tensor() {
        let mut rng = Rng::new(4);
        for order in 1..=12 {
            let unique = rng.values(symmetric_count(order), -1.0, 1.0);
            let f = symmetric(order, &unique);
            let full = expand_symmetric(order, &unique);
            for _ in 0..2 {
                let q = rng.vector(-1.0, 1.0);
                let want = brute_force_full(order, &full, q);
                let tol = 1e-12 * f.abs_eval(q).max(1e-300) * 10.0;
                assert!(
                    close(f.eval(q), want, tol),
                    "order {order}: {} vs {want}",
                    f.eval(q)
                );
            }
        }
    }

    #[test]
    fn gradient_matches_central_differences() {
        let mut rng = Rng::new(5);
        let h = 1e-5;
        for order in 1..=12 {
            let f = symmetric(order, &rng.values(symmetric_count(order), -1.0, 1.0));
            for _ in 0..5 {
                let q = rng.vector(-0.7, 0.7);
                let (value, grad) = f.eval_with_gradient(q);
                assert!(close(value, f.eval(q), 1e-13 * f.abs_eval(q) + 1e-300));
                for axis in 0..3 {
                    let e = DVec3::AXES[axis] * h;
                    let fd = (f.eval(q + e) - f.eval(q - e)) / (2.0 * h);
                    let scale = f.abs_coefficient_sum() * order as f64;
                    assert!(
                        close(grad[axis], fd, 1e-7 * scale),
                        "order {order} axis {axis}: {} vs {fd}",
                        grad[axis]
                    );
                }
            }
        }
    }

    #[test]
    fn along_line_matches_eval() {
        let mut rng = Rng::new(6);
        for order in 1..=12 {
            let f = symmetric(order, &rng.values(symmetric_count(order), -1.0, 1.0));
            let (a, b) = (rng.vector(-1.0, 1.0), rng.vector(-1.0, 1.0));
            let line = f.along_line(a, b);
            assert_eq!(line.len(), order as usize + 1);
            for t in [-1.3, -0.5, 0.0, 0.25, 0.9] {
                let q = a + t * b;
                let tol = 1e-12 * f.abs_eval(q).max(1.0);
                assert!(
                    close(univariate::eval(&line, t), f.eval(q), tol),
                    "order {order}"
                );
            }
        }
    }

    #[test]
    fn abs_eval_bounds_eval_and_is_exact_for_positive_terms() {
        let mut rng = Rng::new(7);
        let f = symmetric(5, &rng.values(21, -1.0, 1.0));
        let positive = symmetric(5, &rng.values(21, 0.0, 1.0));
        for _ in 0..20 {
            let q = rng.vector(-1.0, 1.0);
            assert!(f.eval(q).abs() <= f.abs_eval(q) * (1.0 + 1e-14));
            let qp = q.abs();
            assert!(close(positive.abs_eval(qp), positive.eval(qp), 1e-14));
        }
        assert!(close(
            f.scaled(-2.0).eval(DVec3::ONE),
            -2.0 * f.eval(DVec3::ONE),
            1e-13
        ));
        let sum: f64 = f.coeffs.iter().map(|c| c.abs()).sum();
        assert_eq!(f.abs_coefficient_sum(), sum);
    }

    #[test]
    fn univariate_helpers() {
        let p = [1.0, -3.0, 2.0]; // (1 - t)(1 - 2t)
        assert_eq!(univariate::eval(&p, 0.5), 0.0);
        assert_eq!(univariate::derivative(&p), vec![-3.0, 4.0]);
        assert_eq!(univariate::multiply(&[1.0, -1.0], &[1.0, -2.0]), p.to_vec());
        assert_eq!(univariate::power(&[1.0, 1.0], 3), vec![1.0, 3.0, 3.0, 1.0]);
        assert_eq!(univariate::eval_with_derivative(&p, 2.0), (3.0, 5.0));
        assert_eq!(
            univariate::trimmed(&[1.0, 0.0, 2.0, 0.0, 0.0]),
            &[1.0, 0.0, 2.0]
        );
        assert!(univariate::trimmed(&[0.0, 0.0]).is_empty());
        let mut q = [1.0, 1.0, 0.0];
        univariate::mul_linear_in_place(&mut q, 2.0, 3.0);
        assert_eq!(q, [2.0, 5.0, 3.0]);
    }
}
