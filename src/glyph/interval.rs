//! CPU mirror of the robust ray casters' range arithmetic: the primitives of
//! glsl/range_arithmetic.glsl, the generated `glyph_f_interval` / `glyph_f_affine` of
//! build/range.rs and the segment ranges of glsl/glyph_range.glsl, step for step.
//!
//! Generic over the float type: in float64 it is the reference the property tests hold
//! float64 samples against; in float32 it rounds as the shaders do, so the rounding
//! allowances of [`super::range_rounding`] can be checked on the CPU first.
//!
//! Interval arithmetic (IA) gives each coordinate of a box or segment an interval and
//! evaluates f's monomial sum with interval products; even powers are nonnegative.
//! Reduced affine arithmetic (RAA, Knoll et al., "Fast and robust ray tracing of general
//! implicits on the GPU") writes each coordinate along a segment s = sc + sr eps,
//! eps in [-1, 1], as x0 + x1 eps with one noise symbol, and sweeps every nonlinear
//! remainder into a radius r; its over-estimate shrinks with the square of the segment
//! length where IA's shrinks linearly.
use std::fmt::Debug;
use std::ops::{Add, Mul};

use super::monomials::{Monomial, monomials, multiplicity, nonsymmetric_entry_monomial};
use super::range_rounding::{f_rounding_units, radius_rounding_units};
use super::{NegativeMode, Symmetry, TensorLayout};
use crate::error::Problem;
use crate::{Error, Result};

pub use super::real::Real;

fn half<T: Real>() -> T {
    T::from_f64(0.5)
}

/// The closed interval [lo, hi].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval<T> {
    /// Lower end.
    pub lo: T,
    /// Upper end, >= `lo`.
    pub hi: T,
}

impl<T: Real> Interval<T> {
    /// The interval between `a` and `b`, in either order.
    pub fn new(a: T, b: T) -> Self {
        Interval {
            lo: a.min(b),
            hi: a.max(b),
        }
    }

    fn product(self, b: Self) -> Self {
        let p = [
            self.lo * b.lo,
            self.lo * b.hi,
            self.hi * b.lo,
            self.hi * b.hi,
        ];
        Interval {
            lo: p[0].min(p[1]).min(p[2].min(p[3])),
            hi: p[0].max(p[1]).max(p[2].max(p[3])),
        }
    }

    /// x^k for even k from `ends` = (lo^k, hi^k): nonnegative, 0 when x spans 0.
    pub fn even_power(ends: Self, x: Self) -> Self {
        if x.lo >= T::ZERO {
            ends
        } else if x.hi <= T::ZERO {
            Interval {
                lo: ends.hi,
                hi: ends.lo,
            }
        } else {
            Interval {
                lo: T::ZERO,
                hi: ends.lo.max(ends.hi),
            }
        }
    }

    /// {c x : x in self}, for either sign of c.
    pub fn scale(self, c: T) -> Self {
        if c >= T::ZERO {
            Interval {
                lo: c * self.lo,
                hi: c * self.hi,
            }
        } else {
            Interval {
                lo: c * self.hi,
                hi: c * self.lo,
            }
        }
    }

    /// [lo - by, hi + by].
    pub fn widen(self, by: T) -> Self {
        Interval {
            lo: self.lo - by,
            hi: self.hi + by,
        }
    }

    /// h(f): |f| or max(f, 0).
    pub fn shape(self, negative: NegativeMode) -> Self {
        match negative {
            NegativeMode::Hide => Interval {
                lo: self.lo.max(T::ZERO),
                hi: self.hi.max(T::ZERO),
            },
            NegativeMode::Abs if self.lo >= T::ZERO => self,
            NegativeMode::Abs if self.hi <= T::ZERO => Interval {
                lo: -self.hi,
                hi: -self.lo,
            },
            NegativeMode::Abs => Interval {
                lo: T::ZERO,
                hi: (-self.lo).max(self.hi),
            },
        }
    }

    /// Whether `v` lies in [lo - slack, hi + slack] (ends compared in f64).
    pub fn contains(&self, v: f64, slack: f64) -> bool {
        self.lo.to_f64() - slack <= v && v <= self.hi.to_f64() + slack
    }

    /// hi - lo, in f64.
    pub fn width(&self) -> f64 {
        self.hi.to_f64() - self.lo.to_f64()
    }
}

/// The reduced affine form c + e eps + [-r, r], eps in [-1, 1] the segment's noise symbol.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine<T> {
    /// The centre value c.
    pub c: T,
    /// The coefficient e of the noise symbol eps.
    pub e: T,
    /// The radius r >= 0 of the remainder interval.
    pub r: T,
}

impl<T: Real> Affine<T> {
    /// c + e eps, with no remainder.
    pub const fn exact(c: T, e: T) -> Self {
        Affine { c, e, r: T::ZERO }
    }

    /// The eps^2 term a1 b1 eps^2 is a1 b1 / 2 + (a1 b1 / 2)(2 eps^2 - 1), |2 eps^2 - 1| <= 1.
    fn product(self, b: Self) -> Self {
        let h = half::<T>() * self.e * b.e;
        Affine {
            c: self.c * b.c + h,
            e: self.c * b.e + self.e * b.c,
            r: h.abs()
                + (self.c.abs() + self.e.abs()) * b.r
                + self.r * (b.c.abs() + b.e.abs() + b.r),
        }
    }

    /// k times the form.
    pub fn scale(self, k: T) -> Self {
        Affine {
            c: k * self.c,
            e: k * self.e,
            r: k.abs() * self.r,
        }
    }

    /// The interval the form covers for eps in [-1, 1]: c -+ (|e| + r).
    pub fn range(self) -> Interval<T> {
        let w = self.e.abs() + self.r;
        Interval {
            lo: self.c - w,
            hi: self.c + w,
        }
    }

    /// h(f), affine while f keeps one sign, its interval where f changes sign.
    pub fn shape(self, negative: NegativeMode) -> Self {
        let r = self.range();
        if r.lo >= T::ZERO {
            self
        } else if r.hi <= T::ZERO {
            match negative {
                NegativeMode::Hide => Affine::exact(T::ZERO, T::ZERO),
                NegativeMode::Abs => Affine {
                    c: -self.c,
                    e: -self.e,
                    r: self.r,
                },
            }
        } else {
            let h = r.shape(negative);
            Affine {
                c: half::<T>() * (h.lo + h.hi),
                e: T::ZERO,
                r: half::<T>() * (h.hi - h.lo),
            }
        }
    }
}

impl<T: Real> Mul for Interval<T> {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        self.product(b)
    }
}

impl<T: Real> Add for Interval<T> {
    type Output = Self;
    fn add(self, b: Self) -> Self {
        Interval {
            lo: self.lo + b.lo,
            hi: self.hi + b.hi,
        }
    }
}

impl<T: Real> Mul for Affine<T> {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        self.product(b)
    }
}

impl<T: Real> Add for Affine<T> {
    type Output = Self;
    fn add(self, b: Self) -> Self {
        Affine {
            c: self.c + b.c,
            e: self.e + b.e,
            r: self.r + b.r,
        }
    }
}

/// A ray segment q(s) = mid + s dir, s in [s0, s1], in a glyph's normalised frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RaySegment<T> {
    /// The point at s = 0.
    pub mid: [T; 3],
    /// The direction (not necessarily unit).
    pub dir: [T; 3],
    /// Start parameter.
    pub s0: T,
    /// End parameter.
    pub s1: T,
}

impl<T: Real> RaySegment<T> {
    /// q(s) = mid + s dir.
    pub fn point(&self, s: T) -> [T; 3] {
        std::array::from_fn(|i| self.mid[i] + s * self.dir[i])
    }

    /// Coefficients (c, b, a) of |q(s)|^2 = c + 2 b s + a s^2.
    fn quadratic(&self) -> [T; 3] {
        let dot = |u: &[T; 3], v: &[T; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        [
            dot(&self.mid, &self.mid),
            dot(&self.mid, &self.dir),
            dot(&self.dir, &self.dir),
        ]
    }
}

fn quadratic_at<T: Real>(k: [T; 3], s: T) -> T {
    (k[0] + s * (T::from_f64(2.0) * k[1] + s * k[2])).max(T::ZERO)
}

/// q2^(k/2) by multiplication, as the shader computes it.
fn half_power<T: Real>(q2: T, k: u32) -> T {
    let mut p = T::ONE;
    for _ in 0..k / 2 {
        p = p * q2;
    }
    if k % 2 == 1 { p * q2.sqrt() } else { p }
}

fn power<T: Real>(m: T, k: u32) -> T {
    (0..k).fold(T::ONE, |p, _| p * m)
}

/// Exact range of |q(s)|^2 on the segment: its vertex or an end.
fn radius_squared_range<T: Real>(k: [T; 3], s0: T, s1: T) -> Interval<T> {
    let q0 = quadratic_at(k, s0);
    let q1 = quadratic_at(k, s1);
    let vertex = if k[2] > T::ZERO {
        (-k[1] / k[2]).max(s0).min(s1)
    } else {
        s0
    };
    Interval {
        lo: q0.min(q1).min(quadratic_at(k, vertex)),
        hi: q0.max(q1),
    }
}

/// Affine form of |q(s)|^k (k >= 1) over the segment: convex in s, so below the secant
/// and above the end tangents, which meet at most 2 (sigma - d0)(d1 - sigma) / (d1 - d0)
/// below it (slopes per unit eps).
fn radius_power_affine<T: Real>(k3: [T; 3], s0: T, s1: T, k: u32) -> Affine<T> {
    let sr = half::<T>() * (s1 - s0);
    let q0 = quadratic_at(k3, s0);
    let q1 = quadratic_at(k3, s1);
    let p0 = half_power(q0, k);
    let p1 = half_power(q1, k);
    let dir_len = k3[2].sqrt();
    let tiny = T::from_f64(1e-30);
    let slope = |q: T, s: T| {
        let u = ((k3[1] + s * k3[2]) / q.sqrt().max(tiny))
            .max(-dir_len)
            .min(dir_len);
        T::from_f64(k as f64) * half_power(q, k - 1) * u * sr
    };
    let (d0, d1) = (slope(q0, s0), slope(q1, s1));
    let sigma = half::<T>() * (p1 - p0);
    let spread = d1 - d0;
    let gap = if spread > T::ZERO {
        T::from_f64(2.0) * (sigma - d0).max(T::ZERO) * (d1 - sigma).max(T::ZERO) / spread
    } else {
        T::ZERO
    };
    Affine {
        c: half::<T>() * (p0 + p1) - half::<T>() * gap,
        e: sigma,
        r: half::<T>() * gap,
    }
}

/// How the glyph turns f into a radius: the scene's `negative` mode and the offset w
/// (normalised units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlyphShape<T> {
    /// |f| or max(f, 0).
    pub negative: NegativeMode,
    /// The offset w, in normalised units.
    pub offset: T,
}

/// Ranges of f and of G = h(f) + w |q|^n - |q|^(n+1) over one segment, widened by the
/// rounding allowance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GlyphRange<T> {
    /// The range of f(q).
    pub f: Interval<T>,
    /// The range of G.
    pub g: Interval<T>,
}

/// f in monomial form with the coefficients as the shaders load them, in type T.
#[derive(Clone, Debug, PartialEq)]
pub struct RangePolynomial<T> {
    /// The degree n.
    pub order: u32,
    /// c_k, in the order of `monomials(order)`.
    pub coeffs: Vec<T>,
    /// sum of |stored entry| * multiplicity: abs_sum * m^n bounds sum_k |c_k| |monomial_k|.
    pub abs_sum: T,
    /// Rounding allowance of f's range (unit roundoffs times u).
    pub gamma_f: T,
    /// Rounding allowance of the |q| powers (unit roundoffs times u).
    pub gamma_r: T,
}

impl<T: Real> RangePolynomial<T> {
    /// From a tensor in the scene format's layout, as `glyph_load` folds it: every entry
    /// rounded to T, then times its multiplicity (Eq. 5) or summed into its monomial in
    /// storage order (Eq. 4), in T.
    pub fn from_tensor(layout: TensorLayout, tensor: &[f64]) -> Result<Self> {
        let order = layout.order;
        let max = crate::catalog::max_order(layout.symmetry == crate::glyph::Symmetry::Symmetric);
        if !(1..=max).contains(&order) {
            return Err(Error::data(
                "range polynomial order",
                Problem::OutOfRange {
                    value: order.into(),
                    min: 1.0,
                    max: max.into(),
                },
            ));
        }
        if tensor.len() != layout.coefficient_count() {
            return Err(Error::data(
                "range polynomial coefficients",
                Problem::Count {
                    expected: layout.coefficient_count(),
                    found: tensor.len(),
                },
            ));
        }
        let monos = monomials(order);
        let entries: Vec<T> = tensor.iter().map(|&t| T::from_f64(t)).collect();
        let mut coeffs = vec![T::ZERO; monos.len()];
        let mut abs_sum = T::ZERO;
        let symmetric = layout.symmetry == Symmetry::Symmetric;
        if symmetric {
            for (k, (m, t)) in monos.iter().zip(&entries).enumerate() {
                let mult = T::from_f64(multiplicity(*m) as f64);
                coeffs[k] = mult * *t;
                abs_sum = abs_sum + mult * t.abs();
            }
        } else {
            let mut started = vec![false; monos.len()];
            for (flat, t) in entries.iter().enumerate() {
                let k = monomial_position(&monos, nonsymmetric_entry_monomial(order, flat));
                coeffs[k] = if started[k] { coeffs[k] + *t } else { *t };
                started[k] = true;
                abs_sum = abs_sum + t.abs();
            }
        }
        Ok(RangePolynomial {
            order,
            coeffs,
            abs_sum,
            gamma_f: T::from_f64(f_rounding_units(order, symmetric) * T::UNIT_ROUNDOFF),
            gamma_r: T::from_f64(radius_rounding_units(order) * T::UNIT_ROUNDOFF),
        })
    }

    /// Natural interval extension of f over the box x * y * z (`glyph_f_interval`).
    pub fn f_interval(&self, x: Interval<T>, y: Interval<T>, z: Interval<T>) -> Interval<T> {
        let n = self.order as usize;
        let powers = |v: Interval<T>| {
            let mut out = vec![v; n + 1];
            let mut ends = v;
            for (k, slot) in out.iter_mut().enumerate().skip(2) {
                ends = Interval {
                    lo: ends.lo * v.lo,
                    hi: ends.hi * v.hi,
                };
                *slot = if k % 2 == 0 {
                    Interval::even_power(ends, v)
                } else {
                    ends
                };
            }
            out
        };
        let (px, py, pz) = (powers(x), powers(y), powers(z));
        let mut f = Interval {
            lo: T::ZERO,
            hi: T::ZERO,
        };
        for (c, m) in self.coeffs.iter().zip(monomials(self.order)) {
            let term = monomial_product(m, &px, &py, &pz, |a, b| a * b);
            f = f + term.scale(*c);
        }
        f
    }

    /// Reduced affine extension of f over a segment (`glyph_f_affine`).
    pub fn f_affine(&self, x: Affine<T>, y: Affine<T>, z: Affine<T>) -> Affine<T> {
        let n = self.order as usize;
        let powers = |v: Affine<T>| {
            let mut out = vec![v; n + 1];
            for k in 2..=n {
                out[k] = out[k - 1] * v;
            }
            out
        };
        let (px, py, pz) = (powers(x), powers(y), powers(z));
        let mut f = Affine::exact(T::ZERO, T::ZERO);
        for (c, m) in self.coeffs.iter().zip(monomials(self.order)) {
            let term = monomial_product(m, &px, &py, &pz, |a, b| a * b);
            f = f + term.scale(*c);
        }
        f
    }

    /// f's range over a box, widened by its rounding allowance.
    pub fn f_box_range(&self, x: Interval<T>, y: Interval<T>, z: Interval<T>) -> Interval<T> {
        let m = [x, y, z]
            .iter()
            .fold(T::ZERO, |m, v| m.max(v.lo.abs()).max(v.hi.abs()));
        self.f_interval(x, y, z).widen(self.f_tolerance(m))
    }

    /// Rounding bound of f's range with largest coordinate magnitude m.
    fn f_tolerance(&self, m: T) -> T {
        self.gamma_f * self.abs_sum * power(m, self.order)
    }

    /// Ranges of f and G over a segment by interval arithmetic (`glyph_range_interval`).
    pub fn range_interval(&self, seg: &RaySegment<T>, shape: GlyphShape<T>) -> GlyphRange<T> {
        let (a, b) = (seg.point(seg.s0), seg.point(seg.s1));
        let axis = |i: usize| Interval::new(a[i], b[i]);
        let f = self.f_interval(axis(0), axis(1), axis(2));
        let h = f.shape(shape.negative);
        let q2 = radius_squared_range(seg.quadratic(), seg.s0, seg.s1);
        let n = self.order;
        let rn = (half_power(q2.lo, n), half_power(q2.hi, n));
        let rn1 = (half_power(q2.lo, n + 1), half_power(q2.hi, n + 1));
        let w = shape.offset;
        let g = Interval {
            lo: h.lo + w * rn.0 - rn1.1,
            hi: h.hi + w * rn.1 - rn1.0,
        };
        let m = (0..3).fold(T::ZERO, |m, i| m.max(a[i].abs()).max(b[i].abs()));
        let tol_f = self.f_tolerance(m);
        let tol = tol_f + self.gamma_r * (rn1.1 + w * rn.1);
        GlyphRange {
            f: f.widen(tol_f),
            g: g.widen(tol),
        }
    }

    /// Ranges of f and G over a segment by reduced affine arithmetic
    /// (`glyph_range_affine`).
    pub fn range_affine(&self, seg: &RaySegment<T>, shape: GlyphShape<T>) -> GlyphRange<T> {
        let sc = half::<T>() * (seg.s0 + seg.s1);
        let sr = half::<T>() * (seg.s1 - seg.s0);
        let c = seg.point(sc);
        let e: [T; 3] = std::array::from_fn(|i| sr * seg.dir[i]);
        let axis = |i: usize| Affine::exact(c[i], e[i]);
        let f = self.f_affine(axis(0), axis(1), axis(2));
        let h = f.shape(shape.negative);
        let quad = seg.quadratic();
        let rn = radius_power_affine(quad, seg.s0, seg.s1, self.order);
        let rn1 = radius_power_affine(quad, seg.s0, seg.s1, self.order + 1);
        let w = shape.offset;
        let g = Affine {
            c: h.c + w * rn.c - rn1.c,
            e: h.e + w * rn.e - rn1.e,
            r: h.r + w * rn.r + rn1.r,
        };
        let m = (0..3).fold(T::ZERO, |m, i| m.max(c[i].abs() + e[i].abs()));
        let tol_f = self.f_tolerance(m);
        let tol = tol_f + self.gamma_r * (rn1.range().hi + w * rn.range().hi);
        GlyphRange {
            f: f.range().widen(tol_f),
            g: g.range().widen(tol),
        }
    }
}

fn monomial_position(monos: &[Monomial], m: Monomial) -> usize {
    monos.iter().position(|x| *x == m).unwrap_or(0)
}

/// x^a y^b z^c as the nested products the shaders generate: present factors only, left
/// to right.
fn monomial_product<V: Copy>(
    m: Monomial,
    px: &[V],
    py: &[V],
    pz: &[V],
    mul: impl Fn(V, V) -> V,
) -> V {
    [(px, m.a), (py, m.b), (pz, m.c)]
        .into_iter()
        .filter(|(_, k)| *k > 0)
        .map(|(p, k)| p[k as usize])
        .reduce(mul)
        .unwrap_or(px[0])
}

/// G(q) = h(f(q)) + w |q|^n - |q|^(n+1) at a point, in float64: the value the ranges
/// bound, with f from `poly`.
pub fn homogeneous_g(
    poly: &super::polynomial::GlyphPolynomial,
    shape: GlyphShape<f64>,
    q: glam::DVec3,
) -> f64 {
    let f = poly.eval(q);
    let h = match shape.negative {
        NegativeMode::Abs => f.abs(),
        NegativeMode::Hide => f.max(0.0),
    };
    let r = q.length();
    h + shape.offset * r.powi(poly.order as i32) - r.powi(poly.order as i32 + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn iv(lo: f64, hi: f64) -> Interval<f64> {
        Interval { lo, hi }
    }

    #[test]
    fn interval_products_and_even_powers() {
        assert_eq!(iv(-2.0, 3.0) * iv(-1.0, 4.0), iv(-8.0, 12.0));
        assert_eq!(iv(-3.0, -1.0) * iv(2.0, 5.0), iv(-15.0, -2.0));
        let x = iv(-2.0, 1.0);
        let ends = iv(4.0, 1.0); // (lo^2, hi^2)
        assert_eq!(Interval::even_power(ends, x), iv(0.0, 4.0));
        assert_eq!(
            Interval::even_power(iv(9.0, 1.0), iv(-3.0, -1.0)),
            iv(1.0, 9.0)
        );
        assert_eq!(iv(1.0, 2.0).scale(-3.0), iv(-6.0, -3.0));
        assert_eq!(iv(-3.0, 1.0).shape(NegativeMode::Abs), iv(0.0, 3.0));
        assert_eq!(iv(-3.0, -1.0).shape(NegativeMode::Abs), iv(1.0, 3.0));
        assert_eq!(iv(-3.0, 1.0).shape(NegativeMode::Hide), iv(0.0, 1.0));
    }

    #[test]
    fn affine_square_contains_the_parabola_and_stays_nonnegative_at_its_centre() {
        // x = 0.5 + 1.0 eps; x^2 = 0.25 + eps + eps^2 in [-0.25, 2.25].
        let x = Affine::exact(0.5, 1.0);
        let sq = x * x;
        let range = sq.range();
        for i in 0..=100 {
            let eps = -1.0 + 0.02 * i as f64;
            let v = (0.5 + eps) * (0.5 + eps);
            assert!(range.contains(v, 1e-15), "{v} outside {range:?}");
        }
        // c = 0.25 + 0.5, e = 1, r = 0.5: the range [-0.75, 2.25] is the tight RAA one.
        assert_eq!(
            sq,
            Affine {
                c: 0.75,
                e: 1.0,
                r: 0.5
            }
        );
    }

    #[test]
    fn radius_powers_bound_the_convex_curve_to_second_order() {
        let seg = RaySegment {
            mid: [0.3, -0.2, 0.1],
            dir: [0.0, 0.6, 0.8],
            s0: -0.4,
            s1: 0.7,
        };
        for k in 1..=13 {
            let a = radius_power_affine(seg.quadratic(), seg.s0, seg.s1, k);
            for i in 0..=200 {
                let eps = -1.0 + 0.01 * i as f64;
                let s = 0.15 + 0.55 * eps;
                let p = seg.point(s);
                let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                let value = r.powi(k as i32);
                let lo = a.c + a.e * eps - a.r;
                let hi = a.c + a.e * eps + a.r;
                assert!(
                    lo - 1e-12 <= value && value <= hi + 1e-12,
                    "k {k} eps {eps}: {value} outside [{lo}, {hi}]"
                );
            }
        }
        // Through the centre, |q| = |s| has a kink; the bound still holds.
        let through = RaySegment {
            mid: [0.0; 3],
            dir: [1.0, 0.0, 0.0],
            s0: -0.5,
            s1: 0.25,
        };
        let a = radius_power_affine(through.quadratic(), through.s0, through.s1, 1);
        assert!(a.range().lo <= 0.0 && a.range().hi >= 0.5, "{a:?}");
    }

    #[test]
    fn wrong_coefficient_counts_are_errors() {
        let layout = TensorLayout {
            order: 2,
            symmetry: Symmetry::Symmetric,
        };
        assert!(RangePolynomial::<f32>::from_tensor(layout, &[1.0; 5]).is_err());
        assert!(RangePolynomial::<f32>::from_tensor(layout, &[1.0; 6]).is_ok());
    }
}
