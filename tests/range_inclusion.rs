//! The interval (IA) and reduced affine (RAA) ranges behind `--method interval` and
//! `--method affine` contain what they bound. For random tensors of every variant
//! (symmetric orders 1 to 12, non-symmetric 1 to 4), both negative modes, with and
//! without offset, and random ray segments (some through the centre, lengths 1e-4 to 2),
//! every float64 value of f and of G = h(f) + w |q|^n - |q|^(n+1) at 33 points of the
//! segment lies inside the computed range; for IA also f on random boxes.
//!
//! Tolerance: none beyond the float64 sample's own rounding (a few hundred float64 unit
//! roundoffs of sum |terms|) and 1e-30 absolute for float32 values flushed to zero. The
//! float32 ranges (CPU mirror and GPU) carry their own rounding allowance, which the
//! shaders add themselves (src/glyph/range_rounding.rs: f_rounding_units float32 unit
//! roundoffs, at most ~4e-5 at order 12, of abs_sum * m^n, plus radius_rounding_units of
//! |q|^(n+1)); so this checks that the allowance actually covers float32 rounding.
//!
//! The reference polynomial is built from the float32-rounded tensor entries: the ranges
//! are inclusions for the float32 data the GPU holds, in exact arithmetic.
use crate::common;
use glam::DVec3;
use glyphcast::demo::fibre_tensor;
use glyphcast::glyph::bounds::bounding_radius;
use glyphcast::glyph::interval::{
    GlyphRange, GlyphShape, Interval, RangePolynomial, RaySegment, homogeneous_g,
};
use glyphcast::glyph::monomials::monomials;
use glyphcast::glyph::polynomial::GlyphPolynomial;
use glyphcast::glyph::{NegativeMode, Symmetry, TensorLayout};
use glyphcast::render::harness::range_eval::{RangeQuery, ranges_on_gpu};
use glyphcast::render::shaders::layouts;

const TENSORS_PER_VARIANT: usize = 3;
const SEGMENTS_PER_TENSOR: usize = 120;
const SAMPLES: usize = 33;

/// A small deterministic generator, so failures reproduce.
struct Lcg(u64);
impl Lcg {
    /// Uniform in [-1, 1).
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    fn unit(&mut self) -> f64 {
        0.5 * (self.next() + 1.0)
    }
    fn direction(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.next(), self.next(), self.next());
            if v.length() > 0.1 && v.length() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

fn every_variant() -> Vec<TensorLayout> {
    let all: Vec<TensorLayout> = layouts().collect();
    let expected = (1..=12)
        .map(|order| (order, Symmetry::Symmetric))
        .chain((1..=4).map(|order| (order, Symmetry::NonSymmetric)));
    for (order, symmetry) in expected {
        let layout = TensorLayout { order, symmetry };
        assert!(all.contains(&layout), "no shaders for {layout:?}");
    }
    all
}

/// Random tensors, float32-representable: uniform entries, and for symmetric layouts a
/// glyph of two fibres normalised by its bound (large, cancelling monomial coefficients,
/// as the renderer sees them).
fn tensors(layout: TensorLayout, rng: &mut Lcg) -> Vec<Vec<f64>> {
    let n = layout.coefficient_count();
    (0..TENSORS_PER_VARIANT)
        .map(|i| {
            let raw: Vec<f64> = if i == 0 && layout.symmetry == Symmetry::Symmetric {
                let fibres = [(rng.direction(), 1.0), (rng.direction(), 0.7)];
                let t = fibre_tensor(layout.order, &fibres);
                let poly = GlyphPolynomial::from_tensor(layout, &t).expect("tensor");
                let bound = bounding_radius(&poly, NegativeMode::Abs);
                t.iter().map(|c| c / bound).collect()
            } else {
                (0..n).map(|_| rng.next()).collect()
            };
            raw.iter().map(|&c| c as f32 as f64).collect()
        })
        .collect()
}

fn shape(i: usize) -> GlyphShape<f64> {
    match i % 3 {
        0 => GlyphShape {
            negative: NegativeMode::Abs,
            offset: 0.0,
        },
        1 => GlyphShape {
            negative: NegativeMode::Hide,
            offset: 0.0,
        },
        _ => GlyphShape {
            negative: NegativeMode::Abs,
            offset: 0.25,
        },
    }
}

/// Segments as the ray caster makes them: dir a unit vector, mid the closest point to the
/// centre (one in eight within 1e-3 of it), in the bounding ball; lengths 1e-4 to 2.
fn segments(rng: &mut Lcg) -> Vec<RaySegment<f32>> {
    (0..SEGMENTS_PER_TENSOR)
        .map(|i| {
            let dir = rng.direction();
            let radius = if i % 8 == 0 { 1e-3 } else { 1.2 };
            let p = DVec3::new(rng.next(), rng.next(), rng.next()) * radius;
            let mid = p - p.dot(dir) * dir;
            let len = 10f64.powf(-4.0 + 4.3 * rng.unit());
            let s0 = -1.3 + 2.5 * rng.unit();
            let f = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
            RaySegment {
                mid: f(mid),
                dir: f(dir),
                s0: s0 as f32,
                s1: (s0 + len) as f32,
            }
        })
        .collect()
}

fn to_f64(seg: &RaySegment<f32>) -> RaySegment<f64> {
    RaySegment {
        mid: seg.mid.map(f64::from),
        dir: seg.dir.map(f64::from),
        s0: seg.s0 as f64,
        s1: seg.s1 as f64,
    }
}

/// f and G at a point, with a bound of their float64 rounding.
struct Sample {
    s: f64,
    f: f64,
    g: f64,
    slack: f64,
}

fn samples(poly: &GlyphPolynomial, shape: GlyphShape<f64>, seg: &RaySegment<f64>) -> Vec<Sample> {
    let k = monomials(poly.order).len() as f64;
    let n = poly.order as i32;
    (0..SAMPLES)
        .map(|j| {
            let s = seg.s0 + (seg.s1 - seg.s0) * j as f64 / (SAMPLES - 1) as f64;
            let p = seg.point(s);
            let q = DVec3::new(p[0], p[1], p[2]);
            let r = q.length();
            let scale = poly.abs_eval(q) + r.powi(n + 1) + shape.offset * r.powi(n);
            Sample {
                s,
                f: poly.eval(q),
                g: homogeneous_g(poly, shape, q),
                slack: 4.0 * (k + 2.0 * n as f64 + 8.0) * f64::EPSILON * scale + 1e-30,
            }
        })
        .collect()
}

/// Checks every sample against one method's ranges; returns how many were checked.
fn check(
    what: &str,
    layout: TensorLayout,
    seg: &RaySegment<f64>,
    shape: GlyphShape<f64>,
    samples: &[Sample],
    f: (f64, f64),
    g: (f64, f64),
) -> usize {
    let f = Interval { lo: f.0, hi: f.1 };
    let g = Interval { lo: g.0, hi: g.1 };
    for x in samples {
        assert!(
            f.contains(x.f, x.slack) && g.contains(x.g, x.slack),
            "{what}, {layout:?}, {shape:?}, {seg:?} at s = {}: f {} in {f:?}? G {} in {g:?}?",
            x.s,
            x.f,
            x.g
        );
    }
    samples.len()
}

fn pair<T: glyphcast::glyph::interval::Real>(i: Interval<T>) -> (f64, f64) {
    (i.lo.to_f64(), i.hi.to_f64())
}

fn ranges<T: glyphcast::glyph::interval::Real>(
    poly: &RangePolynomial<T>,
    seg: &RaySegment<f64>,
    shape: GlyphShape<f64>,
) -> [GlyphRange<T>; 2] {
    let t = |v: f64| T::from_f64(v);
    let seg = RaySegment {
        mid: seg.mid.map(t),
        dir: seg.dir.map(t),
        s0: t(seg.s0),
        s1: t(seg.s1),
    };
    let shape = GlyphShape {
        negative: shape.negative,
        offset: t(shape.offset),
    };
    [
        poly.range_interval(&seg, shape),
        poly.range_affine(&seg, shape),
    ]
}

#[test]
fn cpu_ranges_contain_float64_samples_for_every_variant() {
    let mut rng = Lcg(11);
    let mut checked = 0;
    for layout in every_variant() {
        for tensor in tensors(layout, &mut rng) {
            let poly = GlyphPolynomial::from_tensor(layout, &tensor).expect("tensor");
            let mirror64 = RangePolynomial::<f64>::from_tensor(layout, &tensor).expect("f64");
            let mirror32 = RangePolynomial::<f32>::from_tensor(layout, &tensor).expect("f32");
            for (i, seg32) in segments(&mut rng).iter().enumerate() {
                let seg = to_f64(seg32);
                let shape = shape(i);
                let xs = samples(&poly, shape, &seg);
                let names = ["interval", "affine"];
                for (name, r) in names.iter().zip(ranges(&mirror64, &seg, shape)) {
                    let what = format!("{name} f64");
                    checked += check(&what, layout, &seg, shape, &xs, pair(r.f), pair(r.g));
                }
                for (name, r) in names.iter().zip(ranges(&mirror32, &seg, shape)) {
                    let what = format!("{name} f32");
                    checked += check(&what, layout, &seg, shape, &xs, pair(r.f), pair(r.g));
                }
            }
        }
    }
    let expected = 16 * TENSORS_PER_VARIANT * SEGMENTS_PER_TENSOR * SAMPLES * 4;
    assert_eq!(checked, expected);
}

#[test]
fn cpu_interval_contains_f_on_random_boxes() {
    let mut rng = Lcg(5);
    for layout in every_variant() {
        for tensor in tensors(layout, &mut rng) {
            let poly = GlyphPolynomial::from_tensor(layout, &tensor).expect("tensor");
            let mirror64 = RangePolynomial::<f64>::from_tensor(layout, &tensor).expect("f64");
            let mirror32 = RangePolynomial::<f32>::from_tensor(layout, &tensor).expect("f32");
            for _ in 0..100 {
                let centre = DVec3::new(rng.next(), rng.next(), rng.next());
                let half =
                    DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 10f64.powf(-3.0 * rng.unit());
                let (lo, hi) = ((centre - half).as_vec3(), (centre + half).as_vec3());
                let axis = |i: usize| (lo[i], hi[i]);
                let box64 = |i: usize| Interval::new(axis(i).0 as f64, axis(i).1 as f64);
                let box32 = |i: usize| Interval::new(axis(i).0, axis(i).1);
                let r64 = mirror64.f_box_range(box64(0), box64(1), box64(2));
                let r32 = mirror32.f_box_range(box32(0), box32(1), box32(2));
                let k = monomials(layout.order).len() as f64;
                for j in 0..40 {
                    // Corners first, then random points.
                    let t = if j < 8 {
                        DVec3::new((j & 1) as f64, ((j >> 1) & 1) as f64, ((j >> 2) & 1) as f64)
                    } else {
                        DVec3::new(rng.unit(), rng.unit(), rng.unit())
                    };
                    let q = lo.as_dvec3() + t * (hi.as_dvec3() - lo.as_dvec3());
                    let f = poly.eval(q);
                    let slack = 4.0 * (k + 8.0) * f64::EPSILON * poly.abs_eval(q) + 1e-30;
                    assert!(
                        r64.contains(f, slack)
                            && pair(r32).0 - slack <= f
                            && f <= pair(r32).1 + slack,
                        "{layout:?} box {lo}..{hi} at {q}: f {f} in {r64:?} / {r32:?}?"
                    );
                }
            }
        }
    }
}

/// The over-estimate of a range beyond the sampled range of G shrinks linearly with the
/// segment length for IA and quadratically for RAA (where f keeps its sign): the ranges
/// are not just wide enough, they are the arithmetic they claim to be.
#[test]
fn interval_excess_is_first_order_and_affine_excess_second_order() {
    let mut rng = Lcg(3);
    let mut ratios = [Vec::new(), Vec::new()];
    for order in [4, 8, 12] {
        let layout = TensorLayout {
            order,
            symmetry: Symmetry::Symmetric,
        };
        let tensor = &tensors(layout, &mut rng)[0];
        let poly = GlyphPolynomial::from_tensor(layout, tensor).expect("tensor");
        let mirror = RangePolynomial::<f64>::from_tensor(layout, tensor).expect("f64");
        let shape = shape(0);
        while ratios[0].len() < 30 * (order as usize / 4) {
            let q = DVec3::new(rng.next(), rng.next(), rng.next());
            if q.length() < 0.3 || poly.eval(q).abs() < 0.05 * q.length().powi(order as i32) {
                continue;
            }
            let dir = rng.direction();
            let excess = |h: f64| {
                let seg = RaySegment {
                    mid: q.to_array(),
                    dir: dir.to_array(),
                    s0: -h,
                    s1: h,
                };
                let xs = samples(&poly, shape, &seg);
                let lo = xs.iter().map(|x| x.g).fold(f64::INFINITY, f64::min);
                let hi = xs.iter().map(|x| x.g).fold(f64::NEG_INFINITY, f64::max);
                ranges(&mirror, &seg, shape).map(|r| r.g.width() - (hi - lo))
            };
            let (coarse, fine) = (excess(0.02), excess(0.005));
            for m in 0..2 {
                ratios[m].push(coarse[m] / fine[m]);
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (ia, raa) = (median(&mut ratios[0]), median(&mut ratios[1]));
    eprintln!("excess(h) / excess(h / 4), median: interval {ia:.2}, affine {raa:.2}");
    assert!((3.0..6.0).contains(&ia), "interval: {ia}");
    assert!(raa > 10.0, "affine: {raa}");
}

#[test]
fn gpu_ranges_contain_float64_samples_for_every_variant() {
    let gpu = common::gpu();
    let mut rng = Lcg(17);
    let mut checked = 0;
    for layout in every_variant() {
        let tensors = tensors(layout, &mut rng);
        let coefficients: Vec<f32> = tensors.iter().flatten().map(|&c| c as f32).collect();
        let mut queries = Vec::new();
        let mut cases = Vec::new();
        for (glyph, tensor) in tensors.iter().enumerate() {
            let poly = GlyphPolynomial::from_tensor(layout, tensor).expect("tensor");
            for (i, seg) in segments(&mut rng).into_iter().enumerate() {
                let shape = shape(i);
                queries.push(RangeQuery {
                    mid_s0: [seg.mid[0], seg.mid[1], seg.mid[2], seg.s0],
                    dir_s1: [seg.dir[0], seg.dir[1], seg.dir[2], seg.s1],
                    glyph: glyph as u32,
                    hide_negative: shape.negative.shader_code(),
                    offset: shape.offset as f32,
                    pad: 0,
                });
                cases.push((poly.clone(), to_f64(&seg), shape));
            }
        }
        let results =
            ranges_on_gpu(&gpu, layout, &coefficients, &queries).expect("GPU range evaluation");
        assert_eq!(results.len(), queries.len());
        for ((poly, seg, shape), r) in cases.iter().zip(&results) {
            let xs = samples(poly, *shape, seg);
            for (name, v) in [("interval gpu", r.interval), ("affine gpu", r.affine)] {
                let (f, g) = ((v[0] as f64, v[1] as f64), (v[2] as f64, v[3] as f64));
                checked += check(name, layout, seg, *shape, &xs, f, g);
            }
        }
    }
    let expected = 16 * TENSORS_PER_VARIANT * SEGMENTS_PER_TENSOR * SAMPLES * 2;
    assert_eq!(checked, expected);
}
