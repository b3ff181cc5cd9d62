//! Exact float64 ray-glyph intersection: the reference that GPU depth maps are held to.
//!
//! In glyph-local coordinates q = (p - center) / scale the glyph is the set where the
//! radial function
//!
//! ```text
//!   g(q) = h(f(q / |q|)) + offset - |q|        (h = |.| for Abs, max(., 0) for Hide)
//! ```
//!
//! is positive (inside) and its surface is where g changes sign. With offset = 0 and
//! q(t) = a + t b, the function F(t) = f(q(t))^2 - (q.q)^(n+1) (the paper's Eq. 3, squared)
//! is a polynomial of degree 2n + 2 with the sign of g wherever q != 0 (for Hide, g's sign
//! changes are the roots of F where f > 0). F is used only to isolate roots, g to decide:
//!
//! 1. Clip the ray to the bounding sphere |q| <= bound and start at t = 0 if the origin is
//!    inside it.
//! 2. Build F on that chord reparametrised to s in [-1, 1] (centred and scaled, which keeps
//!    the coefficients well conditioned), in float64.
//! 3. Find the critical points of F by the derivative cascade (`real_roots_in` on F'):
//!    between consecutive critical points F is monotone, so it has at most one root there.
//! 4. Near q = 0 F is tiny (~|q|^(2n)) and its computed critical points there can be
//!    wrong, so the sign test uses g, which is well conditioned, at the union of the
//!    critical points and a uniform grid of `GRID_POINTS` points on the chord. The grid
//!    costs 64 evaluations of g and guards against critical points lost to rounding; it
//!    is not needed in exact arithmetic.
//! 5. Bisect g on the first sub-interval whose ends differ in sign, to full float
//!    precision (relative error ~1e-16 of the chord, well below 1e-12 of t).
//!
//! With offset != 0, g is no longer equivalent to a polynomial, so g is sampled at
//! `OFFSET_SAMPLES` uniform points of the chord and the first sign change is bisected;
//! features thinner than chord / 4096 along the ray can be missed there.
//!
//! An ellipsoid glyph ([`GlyphShape::Ellipsoid`]) is a quadric and is intersected in
//! closed form instead ([`ellipsoid::first_hit`]), with the same conventions.
//!
//! A reciprocal glyph ([`GlyphShape::Reciprocal`], r(u) = 1/|f(u)|, f without zeros on
//! the sphere) takes the same steps with g(q) = 1 - |q| |f(q / |q|)| (positive inside,
//! 1 at the centre, which is inside) and F(t) = (q.q)^(n-1) - f(q(t))^2, of degree 2n,
//! which has the sign of g wherever q != 0: |q| |f(q^)| < 1 exactly where
//! |f(q)| = |q|^n |f(q^)| < |q|^(n-1).
//!
//! Conventions: the returned distance is the first root of g with t > 0 along the ray.
//! For a ray that starts outside the glyph this is the entry point; for a ray that starts
//! inside it is the first exit (a camera inside a glyph sees that glyph's inner surface).
//! Roots where g only touches 0 (exact grazing, double roots) are not reported. At q = 0,
//! where the direction is undefined, g is taken as `offset` (so with offset 0 the centre
//! counts as outside, and a lobe whose apex is the centre is entered there).
use glam::DVec3;

use super::bounds::bounding_radius;
use super::ellipsoid::{self, Ellipsoid};
use super::polynomial::{GlyphPolynomial, univariate};
use super::{GlyphShape, NegativeMode};
use crate::Result;
use crate::camera::Ray;

/// Uniform sign-test points added to the critical points of F (step 4 above).
const GRID_POINTS: usize = 64;
/// Samples of g along the chord when offset != 0.
const OFFSET_SAMPLES: usize = 4096;
/// Relative enlargement of the bounding sphere when clipping rays, so that a glyph whose
/// bound is attained exactly (a sphere made by the offset alone) does not start the
/// chord on its own surface, where the sign of g would be decided by rounding.
pub(crate) const BOUND_PADDING: f64 = 1e-6;
/// Iteration cap for bisection and safeguarded Newton (each converges in < 70 halvings).
const MAX_ITERATIONS: usize = 200;

/// A glyph placed in the world: center + scale * r(u) * u.
#[derive(Clone, Debug)]
pub struct WorldGlyph {
    /// Centre, in world units.
    pub center: DVec3,
    /// World length of one local unit (radius 1).
    pub scale: f64,
    /// f, in monomial coefficients; for an ellipsoid, its quadric form x^T D^-1 x
    /// ([`Ellipsoid::quadric_polynomial`]), whose level set 1 is the surface.
    pub poly: GlyphPolynomial,
    /// The polynomial glyph of f, or the ellipsoid of an order-2 tensor.
    pub shape: GlyphShape,
    /// Whether r(u) is |f(u)| or only the part where f(u) > 0.
    pub negative: NegativeMode,
    /// Added to r(u), in local units (0 for the scene format's glyphs).
    pub offset: f64,
    /// upper bound of r(u) over the sphere in local units, offset included
    /// (bounding_radius + offset)
    pub bound: f64,
    /// A plane or ratio glyph's T (its `poly` is D); `None` for the other shapes.
    pub trace: Option<GlyphPolynomial>,
    /// A ratio glyph's Q; `None` for the other shapes.
    pub denominator: Option<GlyphPolynomial>,
}

impl WorldGlyph {
    /// A glyph with its bound computed by [`bounding_radius`].
    pub fn new(
        center: DVec3,
        scale: f64,
        poly: GlyphPolynomial,
        negative: NegativeMode,
        offset: f64,
    ) -> Self {
        let bound = bounding_radius(&poly, negative) + offset;
        Self {
            center,
            scale,
            poly,
            shape: GlyphShape::Polynomial,
            negative,
            offset,
            bound,
            trace: None,
            denominator: None,
        }
    }

    /// The ellipsoid of an order-2 tensor, placed at `center` with `scale`.
    pub fn ellipsoid(center: DVec3, scale: f64, ellipsoid: &Ellipsoid) -> Result<Self> {
        Ok(Self {
            center,
            scale,
            poly: ellipsoid.quadric_polynomial(1.0)?,
            shape: GlyphShape::Ellipsoid,
            negative: NegativeMode::Abs,
            offset: 0.0,
            bound: ellipsoid.radius(),
            trace: None,
            denominator: None,
        })
    }

    /// The reciprocal glyph r(u) = 1/|f(u)| of `poly`, placed at `center` with `scale`;
    /// `None` where f may vanish on the sphere (the surface is unbounded).
    pub fn reciprocal(center: DVec3, scale: f64, poly: GlyphPolynomial) -> Option<Self> {
        let least = super::bounds::least_abs(&poly)?;
        (least.lower > 0.0).then(|| Self {
            center,
            scale,
            poly,
            shape: GlyphShape::Reciprocal,
            negative: NegativeMode::Abs,
            offset: 0.0,
            bound: 1.0 / least.lower,
            trace: None,
            denominator: None,
        })
    }

    /// The plane glyph of `determinant` (D, order 6) and `trace` (T, order 4) with
    /// `shape` [`GlyphShape::PlaneMin`] or `PlaneMax`, placed at `center` with `scale`;
    /// `None` where the roots may not be real and positive everywhere (D may vanish, or
    /// D or T is not positive).
    pub fn plane(
        center: DVec3,
        scale: f64,
        determinant: GlyphPolynomial,
        trace: GlyphPolynomial,
        shape: GlyphShape,
    ) -> Option<Self> {
        let bound = plane_bound(&determinant, &trace)?;
        shape.is_plane().then_some(Self {
            center,
            scale,
            poly: determinant,
            shape,
            negative: NegativeMode::Abs,
            offset: 0.0,
            bound,
            trace: Some(trace),
            denominator: None,
        })
    }

    /// The ratio glyph of `determinant` (D, order 6), `trace` (T, order 4) and
    /// `denominator` (Q, order 4) with `shape` [`GlyphShape::RatioMin`] or `RatioMax`,
    /// placed at `center` with `scale`; `None` where Q may not be positive everywhere
    /// (the surface is unbounded where Q vanishes).
    pub fn ratio(
        center: DVec3,
        scale: f64,
        [determinant, trace, denominator]: [GlyphPolynomial; 3],
        shape: GlyphShape,
    ) -> Option<Self> {
        let bound = ratio_bound(&determinant, &trace, &denominator)?;
        shape.is_ratio().then_some(Self {
            center,
            scale,
            poly: determinant,
            shape,
            negative: NegativeMode::Abs,
            offset: 0.0,
            bound,
            trace: Some(trace),
            denominator: Some(denominator),
        })
    }

    /// A ratio glyph's signed radius along unit `u`: λ/Q of its branch's root of
    /// λ² − T λ + D = 0 (drawn as |λ/Q|, coloured by its sign); 0 for the other shapes.
    pub fn ratio_radius(&self, u: DVec3) -> f64 {
        let (Some(trace), Some(denominator)) = (&self.trace, &self.denominator) else {
            return 0.0;
        };
        let (smaller, larger) = quadratic_roots(trace.eval(u), self.poly.eval(u));
        let lambda = if self.shape == GlyphShape::RatioMin {
            smaller
        } else {
            larger
        };
        lambda / denominator.eval(u)
    }

    /// A plane glyph's radius along unit `u`: 1/λ of its branch's root of
    /// λ² − T λ + D = 0, the eigenvalues of the 2x2 restriction by their trace and
    /// determinant (the smaller one as D / the larger, which does not cancel).
    pub fn plane_radius(&self, u: DVec3) -> f64 {
        let (Some(trace), true) = (&self.trace, self.shape.is_plane()) else {
            return 0.0;
        };
        let (t, d) = (trace.eval(u), self.poly.eval(u));
        let larger = 0.5 * (t + (t * t - 4.0 * d).max(0.0).sqrt());
        if self.shape == GlyphShape::PlaneMin {
            1.0 / larger
        } else {
            larger / d
        }
    }

    /// Radius of the world bounding sphere around `center`.
    pub fn world_radius(&self) -> f64 {
        self.scale * self.bound
    }

    /// g(q) of the module notes, in local coordinates.
    fn radial(&self, q: DVec3) -> f64 {
        let len = q.length();
        if len == 0.0 {
            // The reciprocal glyph holds its centre (g = 1 there).
            return if self.shape == GlyphShape::Reciprocal {
                1.0
            } else {
                self.offset
            };
        }
        if self.shape.is_plane() {
            return self.plane_radius(q / len) - len;
        }
        if self.shape.is_ratio() {
            return self.ratio_radius(q / len).abs() - len;
        }
        let f = self.poly.eval(q / len);
        if self.shape == GlyphShape::Reciprocal {
            return 1.0 - len * f.abs();
        }
        let h = match self.negative {
            NegativeMode::Abs => f.abs(),
            NegativeMode::Hide => f.max(0.0),
        };
        h + self.offset - len
    }
}

/// Distance t > 0 along `ray` (world units of its direction) of the first surface crossing
/// of the glyph, or None: the entry point for rays starting outside, the exit for rays
/// starting inside (see the module notes).
pub fn first_hit(ray: &Ray, glyph: &WorldGlyph) -> Option<f64> {
    if !(glyph.scale > 0.0 && glyph.bound > 0.0) {
        return None;
    }
    if glyph.shape == GlyphShape::Ellipsoid {
        // Local q = (p - c) / scale, so local t is world t / scale.
        let a = (ray.origin - glyph.center) / glyph.scale;
        return ellipsoid::first_hit(&glyph.poly, a, ray.dir).map(|t| t * glyph.scale);
    }
    let chord = Chord::new(ray, glyph)?;
    if glyph.offset == 0.0 {
        chord.first_root_polynomial(glyph)
    } else {
        chord.first_root_sampled(glyph)
    }
}

/// The part [t0, t1] of a ray inside a glyph's bounding sphere, in local coordinates:
/// q(t) = a + t d with t the world distance.
struct Chord {
    a: DVec3,
    d: DVec3,
    t0: f64,
    t1: f64,
}

impl Chord {
    fn new(ray: &Ray, glyph: &WorldGlyph) -> Option<Self> {
        let a = (ray.origin - glyph.center) / glyph.scale;
        let d = ray.dir / glyph.scale;
        let (t_in, t_out) = sphere_interval(a, d, glyph.bound * (1.0 + BOUND_PADDING))?;
        let t0 = t_in.max(0.0);
        (t_out > t0).then_some(Self {
            a,
            d,
            t0,
            t1: t_out,
        })
    }

    fn mid(&self) -> f64 {
        0.5 * (self.t0 + self.t1)
    }

    fn half(&self) -> f64 {
        0.5 * (self.t1 - self.t0)
    }

    /// World distance of the chord parameter s in [-1, 1].
    fn t_of(&self, s: f64) -> f64 {
        self.mid() + self.half() * s
    }

    fn g(&self, glyph: &WorldGlyph, s: f64) -> f64 {
        glyph.radial(self.a + self.t_of(s) * self.d)
    }

    /// Steps 2 to 5 of the module notes.
    fn first_root_polynomial(&self, glyph: &WorldGlyph) -> Option<f64> {
        let f = match (&glyph.trace, &glyph.denominator) {
            (Some(trace), None) if glyph.shape.is_plane() => {
                self.plane_polynomial(&glyph.poly, trace)
            }
            (Some(trace), Some(denominator)) if glyph.shape.is_ratio() => {
                self.ratio_polynomial(&glyph.poly, trace, denominator)
            }
            _ => self.crossing_polynomial(&glyph.poly, glyph.shape),
        };
        let mut points = real_roots_in(&univariate::derivative(&f), -1.0, 1.0);
        points.extend((0..=GRID_POINTS).map(|i| -1.0 + 2.0 * i as f64 / GRID_POINTS as f64));
        points.sort_by(f64::total_cmp);
        points.dedup();
        self.first_sign_change(glyph, &points)
    }

    /// Dense sampling of g when offset != 0.
    fn first_root_sampled(&self, glyph: &WorldGlyph) -> Option<f64> {
        let points: Vec<f64> = (0..=OFFSET_SAMPLES)
            .map(|i| -1.0 + 2.0 * i as f64 / OFFSET_SAMPLES as f64)
            .collect();
        self.first_sign_change(glyph, &points)
    }

    /// F(s) = f(q(s))^2 - (q(s).q(s))^(n+1) on the chord, q(s) = a' + s b'; for the
    /// reciprocal glyph (q(s).q(s))^(n-1) - f(q(s))^2. Either is positive inside.
    fn crossing_polynomial(&self, poly: &GlyphPolynomial, shape: GlyphShape) -> Vec<f64> {
        let a = self.a + self.mid() * self.d;
        let b = self.half() * self.d;
        let f = poly.along_line(a, b);
        let length_squared = [a.length_squared(), 2.0 * a.dot(b), b.length_squared()];
        let mut out = univariate::multiply(&f, &f);
        let (power, sign) = match shape {
            GlyphShape::Reciprocal => (poly.order.saturating_sub(1), -1.0),
            _ => (poly.order + 1, 1.0),
        };
        let radial = univariate::power(&length_squared, power);
        out.resize(out.len().max(radial.len()), 0.0);
        out.iter_mut().for_each(|v| *v *= sign);
        out.iter_mut()
            .zip(&radial)
            .for_each(|(v, r)| *v -= sign * r);
        out
    }

    /// F(s) = T(q)² |q|² − (|q|⁴ + D(q))² of a plane glyph on the chord: both of its
    /// surfaces (the roots are real and positive), positive between them. Its critical
    /// points split the chord into pieces with at most one crossing of either surface,
    /// so the sign changes of the branch's g on them are every crossing of the branch.
    fn plane_polynomial(&self, determinant: &GlyphPolynomial, trace: &GlyphPolynomial) -> Vec<f64> {
        let a = self.a + self.mid() * self.d;
        let b = self.half() * self.d;
        let t = trace.along_line(a, b);
        let d = determinant.along_line(a, b);
        let length_squared = [a.length_squared(), 2.0 * a.dot(b), b.length_squared()];
        let mut outer = univariate::multiply(&length_squared, &length_squared);
        outer.resize(outer.len().max(d.len()), 0.0);
        outer.iter_mut().zip(&d).for_each(|(o, d)| *o += d);
        let mut out = univariate::multiply(&univariate::multiply(&t, &t), &length_squared);
        let square = univariate::multiply(&outer, &outer);
        out.resize(out.len().max(square.len()), 0.0);
        out.iter_mut().zip(&square).for_each(|(o, s)| *o -= s);
        out
    }

    /// F(s) = Q(q)² T(q)² − |q|² (Q(q)² + D(q))² of a ratio glyph on the chord: both of
    /// its branches (|q| (Q² + D) = ±Q T at every point of either surface). Its critical
    /// points split the chord into pieces with at most one crossing of either surface, so
    /// the sign changes of the branch's g on them are every crossing of the branch.
    fn ratio_polynomial(
        &self,
        determinant: &GlyphPolynomial,
        trace: &GlyphPolynomial,
        denominator: &GlyphPolynomial,
    ) -> Vec<f64> {
        let a = self.a + self.mid() * self.d;
        let b = self.half() * self.d;
        let t = trace.along_line(a, b);
        let d = determinant.along_line(a, b);
        let q = denominator.along_line(a, b);
        let length_squared = [a.length_squared(), 2.0 * a.dot(b), b.length_squared()];
        let qt = univariate::multiply(&q, &t);
        let mut inner = univariate::multiply(&q, &q);
        inner.resize(inner.len().max(d.len()), 0.0);
        inner.iter_mut().zip(&d).for_each(|(o, d)| *o += d);
        let mut out = univariate::multiply(&qt, &qt);
        let outer = univariate::multiply(&univariate::multiply(&inner, &inner), &length_squared);
        out.resize(out.len().max(outer.len()), 0.0);
        out.iter_mut().zip(&outer).for_each(|(o, s)| *o -= s);
        out
    }

    /// Bisect the first interval between sorted `points` where g changes sign.
    fn first_sign_change(&self, glyph: &WorldGlyph, points: &[f64]) -> Option<f64> {
        let mut previous: Option<(f64, bool)> = None;
        for &s in points {
            let inside = self.g(glyph, s) > 0.0;
            if let Some((s_prev, was_inside)) = previous
                && inside != was_inside
            {
                let s_root = bisect(|x| self.g(glyph, x) > 0.0, s_prev, s, was_inside);
                return Some(self.t_of(s_root));
            }
            previous = Some((s, inside));
        }
        None
    }
}

/// Parameters (t_in, t_out) where |a + t d| = radius, or None if the line misses.
fn sphere_interval(a: DVec3, d: DVec3, radius: f64) -> Option<(f64, f64)> {
    let dd = d.length_squared();
    if dd == 0.0 {
        return None;
    }
    let mid = -a.dot(d) / dd;
    let closest = a + mid * d;
    let disc = (radius * radius - closest.length_squared()) / dd;
    if disc.is_nan() || disc <= 0.0 {
        return None;
    }
    let half = disc.sqrt();
    Some((mid - half, mid + half))
}

/// Bisection of a predicate that is `at_lo` at `lo` and the opposite at `hi`, to the
/// resolution of f64: returns the point after which it flips.
fn bisect(inside: impl Fn(f64) -> bool, mut lo: f64, mut hi: f64, at_lo: bool) -> f64 {
    for _ in 0..MAX_ITERATIONS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if inside(mid) == at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Roots of a real polynomial (ascending coefficients) in [lo, hi], sorted, by the
/// derivative cascade: the roots of p' cut [lo, hi] into pieces on which p is monotone,
/// each holding at most one root, which safeguarded Newton finds to full precision.
/// The roots of p' come from the same procedure one degree lower, down to degree 1.
///
/// A cut point where |p| is within Horner's rounding error bound is reported as a root;
/// this catches roots of even multiplicity (p touches 0 at a critical point), reported
/// once. The zero polynomial has no isolated roots and gives an empty list.
pub(crate) fn real_roots_in(poly: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let p = univariate::trimmed(poly);
    if lo.is_nan() || hi.is_nan() || lo > hi || p.len() < 2 {
        return Vec::new();
    }
    if p.len() == 2 {
        let root = -p[0] / p[1];
        return if (lo..=hi).contains(&root) {
            vec![root]
        } else {
            Vec::new()
        };
    }
    let mut cuts = vec![lo];
    cuts.extend(real_roots_in(&univariate::derivative(p), lo, hi));
    cuts.push(hi);
    let signs: Vec<i8> = cuts.iter().map(|&t| sign_within_rounding(p, t)).collect();
    let mut roots = Vec::new();
    for (i, (&t, &sign)) in cuts.iter().zip(&signs).enumerate() {
        if sign == 0 {
            roots.push(t);
        } else if i + 1 < cuts.len() && sign * signs[i + 1] < 0 {
            roots.push(newton_bisection(p, t, cuts[i + 1], sign));
        }
    }
    roots.dedup();
    roots
}

/// Sign of p(t), or 0 when |p(t)| is below Horner's error bound 2 d eps sum|p_i||t|^i.
fn sign_within_rounding(p: &[f64], t: f64) -> i8 {
    let value = univariate::eval(p, t);
    let error = 2.0 * p.len() as f64 * f64::EPSILON * univariate::abs_eval(p, t);
    if value.abs() <= error {
        0
    } else if value > 0.0 {
        1
    } else {
        -1
    }
}

/// The root of p in [a, b] where p has sign `sign_a` at a and the opposite at b:
/// Newton steps while they stay in the bracket and at least halve the step, bisection
/// otherwise (the rtsafe scheme), until the step is at f64 resolution.
fn newton_bisection(p: &[f64], mut a: f64, mut b: f64, sign_a: i8) -> f64 {
    let mut x = 0.5 * (a + b);
    let mut step_before = b - a;
    for _ in 0..MAX_ITERATIONS {
        let (value, slope) = univariate::eval_with_derivative(p, x);
        if value == 0.0 {
            return x;
        }
        if (value > 0.0) == (sign_a > 0) {
            a = x;
        } else {
            b = x;
        }
        let newton = x - value / slope;
        let next = if newton > a && newton < b && (newton - x).abs() < 0.5 * step_before {
            newton
        } else {
            0.5 * (a + b)
        };
        step_before = (next - x).abs();
        if next == x || step_before <= 2.0 * f64::EPSILON * x.abs() || b <= a {
            return next;
        }
        x = next;
    }
    x
}

/// A guaranteed bound of a plane glyph's radius 1/λ over the sphere (both roots, so
/// both surfaces lie inside it): the largest radius on a fine sample of directions, raised
/// by a margin and proven to bound every direction (see `plane_radii_below`); where no
/// raised sample is proven (within `PLANE_BOUND_MARGINS`), the crude bound
/// 1/λ ≤ λ' / D ≤ T / D (λ' the other root, both positive), max |T| / min |D| by the
/// bounds of [`super::bounds`]. `None` where D may vanish or D or T is not positive (at x,
/// which stands for every direction once D has no zero: the roots cannot change sign).
pub fn plane_bound(determinant: &GlyphPolynomial, trace: &GlyphPolynomial) -> Option<f64> {
    let least = super::bounds::least_abs(determinant)?;
    let x = DVec3::X;
    if !(least.lower > 0.0 && determinant.eval(x) > 0.0 && trace.eval(x) > 0.0) {
        return None;
    }
    let crude = bounding_radius(trace, NegativeMode::Abs) / least.lower;
    if !(crude.is_finite() && crude > 0.0) {
        return None;
    }
    let radius_at = |u: DVec3| plane_outer_radius(determinant.eval(u), trace.eval(u));
    Some(proven_bound(radius_at, crude, |radius| {
        plane_radii_below(determinant, trace, radius)
    }))
}

/// The first of the sampled largest `radius_at` raised by each of `PLANE_BOUND_MARGINS`
/// that `proven` holds, below `crude`; else `crude`. The sample: `PLANE_BOUND_SAMPLES`
/// directions, the best `PLANE_BOUND_CLIMBS` climbed to their local maxima (still radii
/// the glyph attains).
fn proven_bound(radius_at: impl Fn(DVec3) -> f64, crude: f64, proven: impl Fn(f64) -> bool) -> f64 {
    let sampled = climbed_max(radius_at, PLANE_BOUND_SAMPLES, PLANE_BOUND_CLIMBS);
    PLANE_BOUND_MARGINS
        .iter()
        .map(|margin| sampled * (1.0 + margin))
        .take_while(|&radius| radius < crude)
        .find(|&radius| proven(radius))
        .unwrap_or(crude)
}

/// The largest value of `f` on `samples` directions of a spherical Fibonacci lattice,
/// the best `climbs` of them climbed to their local maxima ([`climb`]): a value `f`
/// attains, near its maximum.
pub(crate) fn climbed_max(f: impl Fn(DVec3) -> f64, samples: usize, climbs: usize) -> f64 {
    let mut values: Vec<(f64, DVec3)> = super::bounds::fibonacci_sphere(samples)
        .map(|u| (f(u), u))
        .collect();
    values.sort_by(|a, b| b.0.total_cmp(&a.0));
    values
        .iter()
        .take(climbs)
        .map(|&(value, u)| climb(&f, value, u))
        .fold(0.0, f64::max)
}

/// The roots (smaller, larger) of λ² − t λ + d = 0, real for a trace and determinant
/// (the discriminant clamped at 0): the one of larger size from the formula, the other
/// as d over it, which does not cancel.
fn quadratic_roots(t: f64, d: f64) -> (f64, f64) {
    let root = (t * t - 4.0 * d).max(0.0).sqrt();
    let big = 0.5 * (t + if t >= 0.0 { root } else { -root });
    let other = if big == 0.0 { 0.0 } else { d / big };
    (big.min(other), big.max(other))
}

/// A guaranteed bound of a ratio glyph's radius |λ/Q| over the sphere (both roots):
/// the largest radius on a fine sample of directions, raised by a margin and proven to
/// bound every direction (see `ratio_radii_below`); where no raised sample is proven
/// (within `PLANE_BOUND_MARGINS`), the crude bound (max |T| + √max |D|) / min Q, from
/// |λ| ≤ |T| + √|D| and the bounds of [`super::bounds`]. `None` where Q may vanish or is
/// not positive.
pub fn ratio_bound(
    determinant: &GlyphPolynomial,
    trace: &GlyphPolynomial,
    denominator: &GlyphPolynomial,
) -> Option<f64> {
    let least = super::bounds::least_abs(denominator)?;
    if !(least.lower > 0.0 && denominator.eval(DVec3::X) > 0.0) {
        return None;
    }
    let crude = (bounding_radius(trace, NegativeMode::Abs)
        + bounding_radius(determinant, NegativeMode::Abs).sqrt())
        / least.lower;
    if !(crude.is_finite() && crude > 0.0) {
        return None;
    }
    let radius_at = |u: DVec3| {
        let (smaller, larger) = quadratic_roots(trace.eval(u), determinant.eval(u));
        smaller.abs().max(larger.abs()) / denominator.eval(u)
    };
    Some(proven_bound(radius_at, crude, |radius| {
        ratio_radii_below(determinant, trace, denominator, radius)
    }))
}

/// Whether both |λ/Q| (λ² − T λ + D = 0, Q > 0 on the sphere, which [`ratio_bound`]
/// checks first) are below `radius` R in every direction, proven: both roots of the
/// upward parabola p(λ) lie in (−R Q, R Q) where p(±R Q) > 0 and its vertex T/2 lies
/// between, that is where the forms R² Q² ∓ R T Q + D |u|² (order 8) and 2 R Q ± T
/// (order 4) are positive on the unit sphere. Each is: its guaranteed least |·| is
/// positive and it is positive at x.
fn ratio_radii_below(
    determinant: &GlyphPolynomial,
    trace: &GlyphPolynomial,
    denominator: &GlyphPolynomial,
    radius: f64,
) -> bool {
    if determinant.order != 6 || trace.order != 4 || denominator.order != 4 {
        return false;
    }
    let square = form_product(denominator, denominator);
    let cross = form_product(trace, denominator);
    let raised = times_length_squared(determinant);
    let combine = |terms: &[(f64, &GlyphPolynomial)]| GlyphPolynomial {
        order: terms[0].1.order,
        coeffs: (0..terms[0].1.coeffs.len())
            .map(|k| terms.iter().map(|(w, f)| w * f.coeffs[k]).sum())
            .collect(),
    };
    let r2 = radius * radius;
    [
        combine(&[(r2, &square), (-radius, &cross), (1.0, &raised)]),
        combine(&[(r2, &square), (radius, &cross), (1.0, &raised)]),
        combine(&[(2.0 * radius, denominator), (-1.0, trace)]),
        combine(&[(2.0 * radius, denominator), (1.0, trace)]),
    ]
    .iter()
    .all(|form| {
        form.eval(DVec3::X) > 0.0 && super::bounds::least_abs(form).is_some_and(|l| l.lower > 0.0)
    })
}

/// The product of two forms, from their monomial coefficients.
fn form_product(a: &GlyphPolynomial, b: &GlyphPolynomial) -> GlyphPolynomial {
    use super::monomials::{Monomial, monomial_index, monomials, symmetric_count};
    let order = a.order + b.order;
    let mut coeffs = vec![0.0; symmetric_count(order)];
    for (ma, ca) in monomials(a.order).into_iter().zip(&a.coeffs) {
        for (mb, cb) in monomials(b.order).into_iter().zip(&b.coeffs) {
            let m = Monomial {
                a: ma.a + mb.a,
                b: ma.b + mb.b,
                c: ma.c + mb.c,
            };
            coeffs[monomial_index(order, m)] += ca * cb;
        }
    }
    GlyphPolynomial { order, coeffs }
}

/// The directions sampled for [`plane_bound`]'s candidate.
const PLANE_BOUND_SAMPLES: usize = 4096;

/// The relative margins tried, in turn, above the largest sampled radius of a plane
/// glyph: the first that [`plane_radii_below`] proves is its bound.
const PLANE_BOUND_MARGINS: [f64; 5] = [1e-3, 1e-2, 5e-2, 0.2, 1.0];

/// The best sampled directions [`plane_bound`] climbs from.
const PLANE_BOUND_CLIMBS: usize = 16;

/// The largest value of `f` found by a pattern search on the unit sphere from `u`
/// (where f is `value`): steps along two tangents, halved when none gains, down to 1e-7.
pub(crate) fn climb(f: impl Fn(DVec3) -> f64, mut value: f64, mut u: DVec3) -> f64 {
    let mut step = 0.05;
    while step > 1e-7 {
        let (e1, e2) = u.any_orthonormal_pair();
        let best = [e1, -e1, e2, -e2]
            .into_iter()
            .map(|e| (u + step * e).normalize())
            .map(|v| (f(v), v))
            .filter(|(w, _)| w.is_finite())
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((w, v)) if w > value => (value, u) = (w, v),
            _ => step *= 0.5,
        }
    }
    value
}

/// The larger radius 1/λ of λ² − t λ + d = 0 (the smaller root λ), t, d > 0: (t + √(t² −
/// 4d)) / (2d), the discriminant clamped at 0.
fn plane_outer_radius(d: f64, t: f64) -> f64 {
    (t + (t * t - 4.0 * d).max(0.0).sqrt()) / (2.0 * d)
}

/// Whether both radii 1/λ (λ² − T λ + D = 0, with D > 0 and T > 0 on the sphere, which
/// [`plane_bound`] checks first) are below `radius` in every direction, proven: with
/// x = 1/λ the roots of D x² − T x + 1, both lie below R exactly where
/// D R² − T R + 1 > 0 and R > T / (2 D) (R beyond the vertex), that is where the two
/// forms of order 6 D(u) R² − T(u) |u|² R + |u|⁶ and 2 R D(u) − T(u) |u|² are positive
/// on the unit sphere. Each is: its guaranteed least |·| ([`super::bounds::least_abs`])
/// is positive, so it has no zero on the sphere (a connected set), and it is positive at
/// x.
fn plane_radii_below(determinant: &GlyphPolynomial, trace: &GlyphPolynomial, radius: f64) -> bool {
    if determinant.order != 6 || trace.order != 4 {
        return false;
    }
    let trace_raised = times_length_squared(trace);
    // |u|⁶, from the constant 1.
    let one = GlyphPolynomial {
        order: 0,
        coeffs: vec![1.0],
    };
    let sphere = times_length_squared(&times_length_squared(&times_length_squared(&one)));
    let outer: Vec<f64> = (0..determinant.coeffs.len())
        .map(|k| {
            determinant.coeffs[k] * radius * radius - trace_raised.coeffs[k] * radius
                + sphere.coeffs[k]
        })
        .collect();
    let vertex: Vec<f64> = (0..determinant.coeffs.len())
        .map(|k| 2.0 * radius * determinant.coeffs[k] - trace_raised.coeffs[k])
        .collect();
    [outer, vertex].into_iter().all(|coeffs| {
        let form = GlyphPolynomial { order: 6, coeffs };
        let positive_at_x = form.eval(DVec3::X) > 0.0;
        positive_at_x && super::bounds::least_abs(&form).is_some_and(|l| l.lower > 0.0)
    })
}

/// The form f(u) |u|² of order n + 2, from f's monomial coefficients.
fn times_length_squared(poly: &GlyphPolynomial) -> GlyphPolynomial {
    use super::monomials::{Monomial, monomial_index, monomials, symmetric_count};
    let order = poly.order + 2;
    let mut coeffs = vec![0.0; symmetric_count(order)];
    for (m, c) in monomials(poly.order).into_iter().zip(&poly.coeffs) {
        for (da, db, dc) in [(2, 0, 0), (0, 2, 0), (0, 0, 2)] {
            let raised = Monomial {
                a: m.a + da,
                b: m.b + db,
                c: m.c + dc,
            };
            coeffs[monomial_index(order, raised)] += c;
        }
    }
    GlyphPolynomial { order, coeffs }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::glyph::monomials::{Monomial, monomial_index, symmetric_count};
    use crate::glyph::polynomial::test_support::Rng;
    use crate::glyph::{Symmetry, TensorLayout};

    fn symmetric(order: u32, t: &[f64]) -> GlyphPolynomial {
        let layout = TensorLayout {
            order,
            symmetry: Symmetry::Symmetric,
        };
        GlyphPolynomial::from_tensor(layout, t).unwrap()
    }

    /// The glyph polynomial sum_i w_i x^a_i y^b_i z^c_i given by monomial coefficients.
    fn from_monomials(order: u32, terms: &[(f64, [u32; 3])]) -> GlyphPolynomial {
        let mut coeffs = vec![0.0; symmetric_count(order)];
        for (w, [a, b, c]) in terms {
            coeffs[monomial_index(
                order,
                Monomial {
                    a: *a,
                    b: *b,
                    c: *c,
                },
            )] += w;
        }
        GlyphPolynomial { order, coeffs }
    }

    fn unit_sphere() -> GlyphPolynomial {
        symmetric(2, &[1.0, 0.0, 0.0, 1.0, 0.0, 1.0])
    }

    /// r = 1/|f| of f = 2 |u|^4 is the sphere of radius 1/2: the first hit of rays
    /// from outside, and the exit of a ray from the centre, in closed form.
    #[test]
    fn reciprocal_of_a_round_quartic_is_a_sphere() {
        // (x^2 + y^2 + z^2)^2 has unique entries 1 at x^4, 1/3 at x^2 y^2 (multiplicity 6).
        let third = 1.0 / 3.0;
        let mut t = [0.0; 15];
        for (k, value) in [
            (0, 1.0),
            (3, third),
            (5, third),
            (10, 1.0),
            (12, third),
            (14, 1.0),
        ] {
            t[k] = 2.0 * value;
        }
        let glyph = WorldGlyph::reciprocal(DVec3::new(0.2, 0.0, 0.0), 3.0, symmetric(4, &t))
            .expect("bounded");
        assert!(
            glyph.bound >= 0.5 && glyph.bound <= 0.5 * 1.02,
            "{}",
            glyph.bound
        );
        let hit = first_hit(
            &ray(DVec3::new(0.2, -5.0, 0.3), DVec3::new(0.2, 0.0, 0.3)),
            &glyph,
        )
        .unwrap();
        let want = 5.0 - (1.5f64 * 1.5 - 0.3 * 0.3).sqrt();
        assert!((hit - want).abs() < 1e-12, "{hit} vs {want}");
        let exit = first_hit(
            &ray(DVec3::new(0.2, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.0)),
            &glyph,
        );
        assert!((exit.unwrap() - 1.5).abs() < 1e-12, "{exit:?}");
    }

    /// Hits of random rays on the reciprocal glyph of a positive quartic lie on
    /// |q| |f(q^)| = 1 to 1e-12, with the ray outside just before; a form that changes
    /// sign on the sphere has no bounded reciprocal glyph.
    #[test]
    fn reciprocal_hits_lie_on_the_surface() {
        let mut rng = Rng::new(7);
        let mut t: Vec<f64> = rng.values(15, -0.1, 0.1);
        for k in [0, 10, 14] {
            t[k] += 1.0;
        }
        let glyph = WorldGlyph::reciprocal(DVec3::ZERO, 1.0, symmetric(4, &t)).unwrap();
        let mut hits = 0;
        for _ in 0..200 {
            let origin = 3.0 * glyph.bound * rng.unit_vector();
            // Inside the sphere of the least radius 1 / max |f|: every ray hits.
            let towards = 0.5 / bounding_radius(&glyph.poly, NegativeMode::Abs) * rng.unit_vector();
            let r = ray(origin, towards);
            let t_hit = first_hit(&r, &glyph).expect("a hit");
            hits += 1;
            let q = r.origin + t_hit * r.dir;
            let g = |q: DVec3| 1.0 - q.length() * glyph.poly.eval(q.normalize()).abs();
            assert!(g(q).abs() < 1e-12, "{}", g(q));
            assert!(g(r.origin + (t_hit - 1e-6) * r.dir) < 0.0);
        }
        assert_eq!(hits, 200);
        let saddle = symmetric(4, &rng.values(15, -1.0, 1.0));
        assert!(WorldGlyph::reciprocal(DVec3::ZERO, 1.0, saddle).is_none());
    }

    fn ray(origin: DVec3, towards: DVec3) -> Ray {
        Ray {
            origin,
            dir: (towards - origin).normalize(),
        }
    }

    /// First intersection with t > 0 of a ray and a sphere (entry, or exit from inside).
    fn analytic_sphere(ray: &Ray, center: DVec3, radius: f64) -> Option<f64> {
        let a = ray.origin - center;
        let mid = -a.dot(ray.dir);
        let disc = mid * mid - (a.length_squared() - radius * radius);
        if disc <= 0.0 {
            return None;
        }
        let (t_in, t_out) = (mid - disc.sqrt(), mid + disc.sqrt());
        [t_in, t_out].into_iter().find(|t| *t > 0.0)
    }

    /// Brute force: g at `samples` uniform points of the bounding chord, then bisection of
    /// the first sign change. Also returns the samples (t, g) for the grazing checks.
    fn brute_force(
        ray: &Ray,
        glyph: &WorldGlyph,
        samples: usize,
    ) -> (Option<f64>, Vec<(f64, f64)>) {
        let Some(chord) = Chord::new(ray, glyph) else {
            return (None, Vec::new());
        };
        let s_of = |i: usize| -1.0 + 2.0 * i as f64 / samples as f64;
        let values: Vec<(f64, f64)> = (0..=samples)
            .map(|i| (chord.t_of(s_of(i)), chord.g(glyph, s_of(i))))
            .collect();
        let hit = (1..=samples).find(|&i| (values[i].1 > 0.0) != (values[i - 1].1 > 0.0));
        let t = hit.map(|i| {
            let at_lo = values[i - 1].1 > 0.0;
            chord.t_of(bisect(
                |s| chord.g(glyph, s) > 0.0,
                s_of(i - 1),
                s_of(i),
                at_lo,
            ))
        });
        (t, values)
    }

    /// Largest g over the brute-force samples with t in [lo, hi]: how deep the ray gets
    /// into the glyph there (radially, local units).
    fn depth_between(values: &[(f64, f64)], lo: f64, hi: f64) -> f64 {
        values
            .iter()
            .filter(|(t, _)| (lo..=hi).contains(t))
            .map(|(_, g)| *g)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Compares `first_hit` with brute force on random rays aimed near the centre.
    /// Both must agree to 1e-9 (relative to max(1, t)) unless the only difference is a
    /// part of the ray that enters the glyph by less than `GRAZE` (radially, local units),
    /// which 20000 samples cannot resolve; returns the number of such grazing rays.
    fn compare_with_brute_force(glyph: &WorldGlyph, rays: usize, seed: u64) -> usize {
        const GRAZE: f64 = 1e-3;
        let mut rng = Rng::new(seed);
        let mut grazing = 0;
        let mut hits = 0;
        let world_radius = glyph.world_radius();
        for _ in 0..rays {
            let origin = glyph.center + 3.0 * world_radius * rng.unit_vector();
            let aim = glyph.center + 0.4 * world_radius * rng.vector(-1.0, 1.0);
            let r = ray(origin, aim);
            let exact = first_hit(&r, glyph);
            let (sampled, values) = brute_force(&r, glyph, 20_000);
            hits += usize::from(exact.is_some());
            match (exact, sampled) {
                (None, None) => {}
                (Some(a), Some(b)) if (a - b).abs() <= 1e-9 * a.max(1.0) => {}
                (Some(a), Some(b)) if a < b => {
                    // first_hit found an earlier crossing: only a graze is allowed there.
                    assert!(depth_between(&values, a, b - 1e-9) < GRAZE, "{a} vs {b}");
                    grazing += 1;
                }
                (Some(a), None) => {
                    assert!(
                        depth_between(&values, a, f64::INFINITY) < GRAZE,
                        "{a} vs miss"
                    );
                    grazing += 1;
                }
                (exact, sampled) => panic!("first_hit {exact:?}, brute force {sampled:?}"),
            }
        }
        assert!(hits > rays / 4, "too few hits to test anything: {hits}");
        grazing
    }

    #[test]
    fn sphere_glyph_matches_analytic_intersection() {
        let mut rng = Rng::new(21);
        let (center, scale) = (DVec3::new(0.3, -1.0, 2.0), 1.7);
        let glyph = WorldGlyph::new(center, scale, unit_sphere(), NegativeMode::Abs, 0.0);
        let mut hits = 0;
        for _ in 0..2000 {
            let origin = center + rng.vector(-6.0, 6.0);
            let r = ray(origin, center + rng.vector(-2.5, 2.5));
            let exact = analytic_sphere(&r, center, scale);
            let a = r.origin - center;
            let mid = -a.dot(r.dir);
            let disc = mid * mid - (a.length_squared() - scale * scale);
            if disc.abs() < 1e-9 {
                continue; // grazing: either answer is right
            }
            match (first_hit(&r, &glyph), exact) {
                (Some(t), Some(want)) => {
                    assert!((t - want).abs() <= 1e-12 * want.max(1.0), "{t} vs {want}");
                    hits += 1;
                }
                (None, None) => {}
                (got, want) => panic!("first_hit {got:?}, analytic {want:?}"),
            }
        }
        assert!(hits > 500);
    }

    #[test]
    fn ray_starting_inside_returns_the_exit() {
        let glyph = WorldGlyph::new(DVec3::ZERO, 2.0, unit_sphere(), NegativeMode::Abs, 0.0);
        let r = Ray {
            origin: DVec3::new(0.5, 0.0, 0.0),
            dir: DVec3::X,
        };
        let t = first_hit(&r, &glyph).unwrap();
        assert!((t - 1.5).abs() < 1e-12, "{t}");
    }

    #[test]
    fn rays_that_miss() {
        let center = DVec3::new(1.0, 2.0, 3.0);
        let glyph = WorldGlyph::new(center, 0.5, unit_sphere(), NegativeMode::Abs, 0.0);
        let away = Ray {
            origin: center + DVec3::new(0.0, 0.0, 2.0),
            dir: DVec3::Z,
        };
        let beside = Ray {
            origin: center + DVec3::new(0.6, -5.0, 0.0),
            dir: DVec3::Y,
        };
        let just_outside_bound = Ray {
            origin: center + DVec3::new(0.502, -5.0, 0.0),
            dir: DVec3::Y,
        };
        let behind = Ray {
            origin: center + DVec3::new(0.0, 1.0, 0.0),
            dir: DVec3::Y,
        };
        for r in [away, beside, just_outside_bound, behind] {
            assert_eq!(first_hit(&r, &glyph), None, "{r:?}");
        }
        let zero = GlyphPolynomial {
            order: 4,
            coeffs: vec![0.0; 15],
        };
        let empty = WorldGlyph::new(center, 1.0, zero, NegativeMode::Abs, 0.0);
        assert_eq!(
            first_hit(&ray(center - DVec3::X * 3.0, center), &empty),
            None
        );
    }

    #[test]
    fn lobes_touching_the_centre_match_brute_force() {
        let glyphs = [
            (
                "x^8 + y^8",
                from_monomials(8, &[(1.0, [8, 0, 0]), (1.0, [0, 8, 0])]),
            ),
            ("x^2 y^2", from_monomials(4, &[(1.0, [2, 2, 0])])),
            (
                "x^4 - 2 y^2 z^2 + z^4",
                from_monomials(4, &[(1.0, [4, 0, 0]), (-2.0, [0, 2, 2]), (1.0, [0, 0, 4])]),
            ),
        ];
        for (i, (name, poly)) in glyphs.into_iter().enumerate() {
            let glyph = WorldGlyph::new(
                DVec3::new(0.5, 0.2, -0.1),
                0.8,
                poly,
                NegativeMode::Abs,
                0.0,
            );
            let grazing = compare_with_brute_force(&glyph, 150, 30 + i as u64);
            assert!(grazing <= 3, "{name}: {grazing} grazing rays");
        }
    }

    /// A ray tangent to the surface at the surface point in direction `u`, pushed into
    /// the glyph by `depth` along the normal: its crossing is ~sqrt(depth) long.
    fn grazing_ray(glyph: &WorldGlyph, u: DVec3, depth: f64, side: DVec3) -> Ray {
        // r(u) = g(u) + |u| on the unit sphere.
        let surface = glyph.center + glyph.scale * (glyph.radial(u) + 1.0) * u;
        let g = |x: DVec3| glyph.radial((x - glyph.center) / glyph.scale);
        let h = 1e-7;
        let inward =
            DVec3::from_array(DVec3::AXES.map(|e| g(surface + h * e) - g(surface - h * e)))
                .normalize();
        let dir = inward.cross(side).normalize();
        let through = surface + depth * glyph.scale * inward;
        Ray {
            origin: through - 3.0 * glyph.world_radius() * dir,
            dir,
        }
    }

    /// Rays that graze the sides of thin lobes (x^12 + y^12, and a random order-6 glyph)
    /// cross the glyph over lengths far below the 64-point grid spacing, so only the
    /// critical points of F (the derivative cascade) isolate those crossings.
    #[test]
    fn grazing_crossings_need_the_derivative_cascade() {
        let mut rng = Rng::new(35);
        let random = symmetric(6, &rng.values(symmetric_count(6), -1.0, 1.0));
        let thin = from_monomials(12, &[(1.0, [12, 0, 0]), (1.0, [0, 12, 0])]);
        for poly in [thin, random] {
            let glyph =
                WorldGlyph::new(DVec3::new(0.2, 0.1, 0.0), 1.5, poly, NegativeMode::Abs, 0.0);
            let mut short_crossings = 0;
            for _ in 0..150 {
                // Surface points away from the centre, where a tangent ray is well defined.
                let u = std::iter::repeat_with(|| rng.unit_vector())
                    .find(|&u| glyph.radial(u) + 1.0 > 0.3)
                    .unwrap();
                let depth = 10f64.powf(rng.uniform(-6.0, -3.0));
                let r = grazing_ray(&glyph, u, depth, rng.unit_vector());
                let exact = first_hit(&r, &glyph);
                let (sampled, values) = brute_force(&r, &glyph, 20_000);
                match (exact, sampled) {
                    (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-9 * a.max(1.0), "{a} vs {b}"),
                    (None, None) => {}
                    (Some(a), None) => assert!(depth_between(&values, a, f64::INFINITY) < 1e-6),
                    (None, Some(b)) => panic!("first_hit missed the crossing at {b}"),
                }
                // Samples in the first run inside the glyph, against the grid spacing.
                let first_run = values
                    .iter()
                    .skip_while(|(_, g)| *g <= 0.0)
                    .take_while(|(_, g)| *g > 0.0)
                    .count();
                let spacing = values.len() / GRID_POINTS;
                short_crossings += usize::from(first_run > 0 && first_run < spacing / 2);
            }
            assert!(
                short_crossings > 30,
                "only {short_crossings} short crossings"
            );
        }
    }

    #[test]
    fn random_glyphs_match_brute_force() {
        let mut rng = Rng::new(40);
        for (order, negative) in [
            (3, NegativeMode::Hide),
            (4, NegativeMode::Abs),
            (6, NegativeMode::Abs),
            (5, NegativeMode::Hide),
        ] {
            let poly = symmetric(order, &rng.values(symmetric_count(order), -1.0, 1.0));
            let glyph = WorldGlyph::new(rng.vector(-1.0, 1.0), 1.3, poly, negative, 0.0);
            let grazing = compare_with_brute_force(&glyph, 100, 41 + u64::from(order));
            assert!(grazing <= 3, "order {order}: {grazing} grazing rays");
        }
    }

    #[test]
    fn hide_drops_negative_lobes() {
        // f = x^3: a lobe of radius 1 along +x (f > 0) and one along -x (f < 0).
        let poly = from_monomials(3, &[(1.0, [3, 0, 0])]);
        let abs = WorldGlyph::new(DVec3::ZERO, 1.0, poly.clone(), NegativeMode::Abs, 0.0);
        let hide = WorldGlyph::new(DVec3::ZERO, 1.0, poly, NegativeMode::Hide, 0.0);
        let from_minus_x = Ray {
            origin: DVec3::new(-5.0, 0.0, 0.0),
            dir: DVec3::X,
        };
        let from_plus_x = Ray {
            origin: DVec3::new(5.0, 0.0, 0.0),
            dir: -DVec3::X,
        };
        let near = |got: Option<f64>, want: f64| got.is_some_and(|t| (t - want).abs() < 1e-12);
        assert!(near(first_hit(&from_minus_x, &abs), 4.0));
        // Hide: no -x lobe; the +x lobe's apex is the centre, where the ray enters it.
        assert!(near(first_hit(&from_minus_x, &hide), 5.0));
        assert!(near(first_hit(&from_plus_x, &abs), 4.0));
        assert!(near(first_hit(&from_plus_x, &hide), 4.0));
        // A ray through the -x lobe only: hit under Abs, nothing under Hide.
        let minus_lobe_only = ray(DVec3::new(-0.5, -3.0, 0.0), DVec3::new(-0.5, 0.0, 0.0));
        assert!(first_hit(&minus_lobe_only, &abs).is_some());
        assert_eq!(first_hit(&minus_lobe_only, &hide), None);
        let hide_max = hide.bound;
        assert!((1.0..1.02).contains(&hide_max), "{hide_max}");
    }

    #[test]
    fn offset_glyphs_are_spheres_when_f_is_constant_on_the_sphere() {
        let mut rng = Rng::new(50);
        let zero = GlyphPolynomial {
            order: 4,
            coeffs: vec![0.0; 15],
        };
        let cases = [(zero, 0.6, 0.6), (unit_sphere(), 0.5, 1.5)];
        for (poly, offset, radius) in cases {
            let center = DVec3::new(-0.2, 0.4, 1.0);
            let glyph = WorldGlyph::new(center, 2.0, poly, NegativeMode::Abs, offset);
            for _ in 0..200 {
                let r = ray(
                    center + rng.vector(-8.0, 8.0),
                    center + rng.vector(-3.0, 3.0),
                );
                match (
                    first_hit(&r, &glyph),
                    analytic_sphere(&r, center, 2.0 * radius),
                ) {
                    (Some(t), Some(want)) => assert!((t - want).abs() <= 1e-12 * want.max(1.0)),
                    (None, None) => {}
                    (got, want) => panic!("first_hit {got:?}, analytic {want:?}"),
                }
            }
        }
    }

    fn from_roots(roots: &[f64]) -> Vec<f64> {
        roots
            .iter()
            .fold(vec![1.0], |p, r| univariate::multiply(&p, &[-r, 1.0]))
    }

    fn assert_roots(found: &[f64], want: &[f64], tol: f64) {
        assert_eq!(found.len(), want.len(), "found {found:?}, want {want:?}");
        for (f, w) in found.iter().zip(want) {
            assert!((f - w).abs() <= tol, "found {found:?}, want {want:?}");
        }
    }

    #[test]
    fn real_roots_of_products_of_linear_factors() {
        let mut rng = Rng::new(60);
        for degree in 1..=12 {
            let mut roots = rng.values(degree, -1.0, 1.0);
            roots.sort_by(f64::total_cmp);
            if roots.windows(2).any(|w| w[1] - w[0] < 1e-2) {
                continue; // close pairs are tested separately
            }
            let scale = rng.uniform(0.5, 3.0);
            let p: Vec<f64> = from_roots(&roots).iter().map(|c| c * scale).collect();
            assert_roots(&real_roots_in(&p, -1.5, 1.5), &roots, 1e-10);
        }
    }

    #[test]
    fn real_roots_only_inside_the_interval() {
        let p = from_roots(&[-2.0, -0.5, 0.25, 3.0]);
        assert_roots(&real_roots_in(&p, -1.0, 1.0), &[-0.5, 0.25], 1e-14);
        assert_roots(&real_roots_in(&p, 0.3, 2.9), &[], 0.0);
        assert_roots(&real_roots_in(&[1.0, 1.0, 1.0], -10.0, 10.0), &[], 0.0); // no real roots
        assert_roots(&real_roots_in(&[0.0, 0.0], -1.0, 1.0), &[], 0.0);
        assert_roots(&real_roots_in(&[0.5, -1.0, 0.0], -1.0, 1.0), &[0.5], 0.0);
    }

    /// Roots as accurate as the float coefficients allow: rounding p's coefficients moves
    /// a simple root r by up to eps sum|p_i||r|^i / |p'(r)|, Horner adds 2 d times that.
    fn assert_roots_conditioned(p: &[f64], found: &[f64], want: &[f64]) {
        assert_eq!(found.len(), want.len(), "found {found:?}, want {want:?}");
        for (f, &w) in found.iter().zip(want) {
            let slope = univariate::eval(&univariate::derivative(p), w).abs();
            let tol = 4.0 * p.len() as f64 * f64::EPSILON * univariate::abs_eval(p, w) / slope;
            assert!(
                (f - w).abs() <= tol,
                "found {found:?}, want {want:?} (tol {tol:e})"
            );
        }
    }

    #[test]
    fn real_roots_close_and_multiple() {
        let pair = [-0.5, 0.3, 0.3 + 1e-4, 0.7];
        assert_roots(&real_roots_in(&from_roots(&pair), -1.0, 1.0), &pair, 1e-10);
        let cluster = [-0.5, 0.3, 0.3 + 1e-5, 0.3 + 3e-5];
        let p = from_roots(&cluster);
        assert_roots_conditioned(&p, &real_roots_in(&p, -1.0, 1.0), &cluster);
        let double = from_roots(&[0.2, 0.2, -0.4]);
        assert_roots(&real_roots_in(&double, -1.0, 1.0), &[-0.4, 0.2], 1e-7);
    }

    #[test]
    fn real_roots_degree_26() {
        // The degree of F at order 12: 26 roots spread over [-1, 1], jittered.
        let mut rng = Rng::new(61);
        let roots: Vec<f64> = (0..26)
            .map(|i| -0.96 + 1.92 * i as f64 / 25.0 + rng.uniform(-0.01, 0.01))
            .collect();
        assert_roots(&real_roots_in(&from_roots(&roots), -1.0, 1.0), &roots, 1e-8);
        // A degree-26 polynomial with three real roots in [-1, 1], one outside and eleven
        // complex pairs (factors t^2 + r^2 > 0).
        let mut mixed = from_roots(&[-0.7, 0.1, 0.55, 2.0]);
        for k in 0..11 {
            let r = 0.05 + 0.1 * k as f64;
            mixed = univariate::multiply(&mixed, &[r * r, 0.0, 1.0]);
        }
        assert_eq!(mixed.len(), 27);
        assert_roots(&real_roots_in(&mixed, -1.0, 1.0), &[-0.7, 0.1, 0.55], 1e-10);
    }

    /// A plane glyph whose roots are two quadratic forms, λ = Q1(u) and Q2(u) at unit u
    /// (T = (Q1 + Q2) |u|², D = Q1 Q2 |u|²), which cross along curves as a cubic
    /// crystal's shear surfaces do: its largest radius is 1 / (the least eigenvalue of
    /// Q1 and Q2). plane_bound holds it, within 0.11 %, far below the crude T / D bound.
    #[test]
    fn plane_bound_is_guaranteed_and_tight() {
        // Q = R diag R^T as monomial coefficients x², xy, xz, y², yz, z².
        let quadratic = |m: [[f64; 3]; 3]| GlyphPolynomial {
            order: 2,
            coeffs: vec![
                m[0][0],
                2.0 * m[0][1],
                2.0 * m[0][2],
                m[1][1],
                2.0 * m[1][2],
                m[2][2],
            ],
        };
        let q1 = quadratic([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]);
        // diag(0.8, 4, 2) turned by 0.5 rad about z.
        let (c, s) = (0.5f64.cos(), 0.5f64.sin());
        let (a, b) = (0.8, 4.0);
        let q2 = quadratic([
            [a * c * c + b * s * s, (a - b) * c * s, 0.0],
            [(a - b) * c * s, a * s * s + b * c * c, 0.0],
            [0.0, 0.0, 2.0],
        ]);
        let length = quadratic([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let trace = form_product(
            &GlyphPolynomial {
                order: 2,
                coeffs: q1
                    .coeffs
                    .iter()
                    .zip(&q2.coeffs)
                    .map(|(a, b)| a + b)
                    .collect(),
            },
            &length,
        );
        let determinant = form_product(&form_product(&q1, &q2), &length);
        let truth = 1.0 / 0.8;
        let bound = plane_bound(&determinant, &trace).unwrap();
        assert!(
            bound >= truth && bound <= 1.0011 * truth,
            "{bound} against {truth}"
        );
        let least = crate::glyph::bounds::least_abs(&determinant).unwrap().lower;
        let crude = bounding_radius(&trace, NegativeMode::Abs) / least;
        assert!(crude > 1.5 * bound, "crude {crude}, bound {bound}");
        // Both radii lie below it in every sampled direction, and the glyph's radius
        // function is the smaller root's 1 / min(Q1, Q2).
        let glyph = WorldGlyph::plane(
            DVec3::ZERO,
            1.0,
            determinant.clone(),
            trace.clone(),
            GlyphShape::PlaneMax,
        )
        .unwrap();
        let mut rng = Rng::new(7);
        for _ in 0..2000 {
            let u = rng.unit_vector();
            let want = 1.0 / q1.eval(u).min(q2.eval(u));
            assert!((glyph.plane_radius(u) / want - 1.0).abs() < 1e-9, "{u}");
            assert!(want <= bound);
        }
        // A proof that fails below the truth.
        assert!(!plane_radii_below(&determinant, &trace, 0.99 * truth));
    }

    /// A ratio glyph whose roots over Q are two quadratic forms of both signs, λ/Q =
    /// Q1(u) and Q2(u) at unit u (T = (Q1 + Q2) |u|², D = Q1 Q2 |u|², Q = |u|⁴): its
    /// largest |radius| is 3 (Q1 = x² + 2y² − 3z² along z). ratio_bound holds it within
    /// 0.1 %, the proof fails below it, and each branch's signed radius is min or max of
    /// Q1 and Q2.
    #[test]
    fn ratio_bound_is_guaranteed_and_tight() {
        let q1 = from_monomials(2, &[(1.0, [2, 0, 0]), (2.0, [0, 2, 0]), (-3.0, [0, 0, 2])]);
        let q2 = from_monomials(2, &[(0.5, [2, 0, 0]), (0.5, [0, 2, 0]), (0.5, [0, 0, 2])]);
        let sum = GlyphPolynomial {
            order: 2,
            coeffs: q1
                .coeffs
                .iter()
                .zip(&q2.coeffs)
                .map(|(a, b)| a + b)
                .collect(),
        };
        let trace = times_length_squared(&sum);
        let determinant = times_length_squared(&form_product(&q1, &q2));
        let one = GlyphPolynomial {
            order: 0,
            coeffs: vec![1.0],
        };
        let denominator = times_length_squared(&times_length_squared(&one));
        let bound = ratio_bound(&determinant, &trace, &denominator).unwrap();
        assert!((3.0..=3.003).contains(&bound), "{bound}");
        assert!(!ratio_radii_below(&determinant, &trace, &denominator, 2.97));
        let forms = [determinant, trace, denominator];
        let mut rng = Rng::new(11);
        for (shape, pick) in [
            (GlyphShape::RatioMin, f64::min as fn(f64, f64) -> f64),
            (GlyphShape::RatioMax, f64::max),
        ] {
            let glyph = WorldGlyph::ratio(DVec3::ZERO, 1.0, forms.clone(), shape).unwrap();
            for _ in 0..2000 {
                let u = rng.unit_vector();
                let want = pick(q1.eval(u), q2.eval(u));
                assert!((glyph.ratio_radius(u) - want).abs() < 1e-12, "{u}");
            }
        }
        // A Q that vanishes somewhere has no bound.
        let [determinant, trace, _] = forms;
        let tilted = times_length_squared(&q1);
        assert!(ratio_bound(&determinant, &trace, &tilted).is_none());
    }
}
