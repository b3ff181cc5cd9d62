//! Global extremes of the directional moduli over all directions.
//!
//! Linear compressibility is a quadratic form in `u`, so its extremes are the
//! eigenvalues of the 3x3 matrix `β_ij = Σ_k s_ijkk`. Young's modulus, the shear
//! modulus and Poisson's ratio are searched: every direction `u` of a Fibonacci set of
//! [`SEED_COUNT`] points on the half sphere (the moduli are even in `u`) is scored,
//! with the exact extremes over `v ⊥ u` for shear and Poisson; the best
//! [`REFINED_SEEDS`] scores at least [`SEED_SEPARATION`] apart are refined locally by
//! Nelder–Mead, over the sphere for `E` and over orthonormal pairs `(u, v)` (a
//! rotation of a frame) for `G` and `ν`, where the function is smooth even where the
//! two extremes over `v` cross. The best refined point wins.

use nalgebra::{Matrix3, SymmetricEigen};
use serde::{Deserialize, Serialize};

use crate::stiffness::{Stiffness, cross, dot, normalized, plane_basis};

/// Directions scored on the half sphere to seed the local searches.
pub const SEED_COUNT: usize = 6000;

/// How many of the best-scored, mutually separated seeds are refined.
pub const REFINED_SEEDS: usize = 12;

/// The least angle (radians, between lines) between two refined seeds.
pub const SEED_SEPARATION: f64 = 0.15;

/// The extremes over all directions of a modulus of one direction, and where.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DirectionalExtremes {
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// A unit direction where the value is `min`.
    pub min_direction: [f64; 3],
    /// A unit direction where the value is `max`.
    pub max_direction: [f64; 3],
}

/// The extremes over all perpendicular unit pairs `(u, v)` of a modulus of two
/// directions, and where.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PairExtremes {
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// The pair `[u, v]` where the value is `min`.
    pub min_pair: [[f64; 3]; 2],
    /// The pair `[u, v]` where the value is `max`.
    pub max_pair: [[f64; 3]; 2],
}

impl Stiffness {
    /// The smallest and largest Young's modulus over all directions, with the
    /// directions reaching them (searched, as the [crate](crate) notes describe).
    pub fn young_extremes(&self) -> DirectionalExtremes {
        // E = 1/q with q(u) = s(u,u,u,u): search q, which stays finite.
        let q = |u: [f64; 3]| self.inverse_young_unit(u);
        let min_direction = search_sphere(&|u| -q(u));
        let max_direction = search_sphere(&q);
        let (a, b) = (1.0 / q(min_direction), 1.0 / q(max_direction));
        if a <= b {
            DirectionalExtremes {
                min: a,
                max: b,
                min_direction,
                max_direction,
            }
        } else {
            DirectionalExtremes {
                min: b,
                max: a,
                min_direction: max_direction,
                max_direction: min_direction,
            }
        }
    }

    /// The smallest and largest linear compressibility, exactly: the extreme
    /// eigenvalues of `β_ij = Σ_k s_ijkk`, with their eigenvectors.
    pub fn compressibility_extremes(&self) -> DirectionalExtremes {
        let beta = self.compressibility_matrix();
        let eigen = SymmetricEigen::new(Matrix3::from_fn(|i, j| beta[i][j]));
        let (lowest, highest) = (eigen.eigenvalues.imin(), eigen.eigenvalues.imax());
        let direction = |k: usize| std::array::from_fn(|i| eigen.eigenvectors[(i, k)]);
        DirectionalExtremes {
            min: eigen.eigenvalues[lowest],
            max: eigen.eigenvalues[highest],
            min_direction: direction(lowest),
            max_direction: direction(highest),
        }
    }

    /// The smallest and largest shear modulus over all perpendicular pairs: the
    /// minimum over `u` of `Gmin(u)` and the maximum over `u` of `Gmax(u)` (searched,
    /// as the [crate](crate) notes describe).
    pub fn shear_extremes(&self) -> PairExtremes {
        // 1/G = 4 s(u,v,u,v) is smooth and finite: search it.
        let inverse = |u: [f64; 3], v: [f64; 3]| self.inverse_shear_unit(u, v);
        let inner_high = |u| {
            let e = self.shear_min_max_unit(u);
            (1.0 / e.min, e.min_v)
        };
        let inner_low = |u| {
            let e = self.shear_min_max_unit(u);
            (1.0 / e.max, e.max_v)
        };
        let low = search_pairs(&|u, v| -inverse(u, v), &|u| {
            let (value, v) = inner_high(u);
            (-value, v)
        });
        let high = search_pairs(&inverse, &inner_low);
        let value = |[u, v]: [[f64; 3]; 2]| 1.0 / inverse(u, v);
        pair_extremes(value(low), low, value(high), high)
    }

    /// The smallest and largest Poisson's ratio over all perpendicular pairs: the
    /// minimum over `u` of `νmin(u)` and the maximum over `u` of `νmax(u)` (searched,
    /// as the [crate](crate) notes describe).
    pub fn poisson_extremes(&self) -> PairExtremes {
        let nu = |u: [f64; 3], v: [f64; 3]| self.poisson_unit(u, v);
        let low = search_pairs(&nu, &|u| {
            let e = self.poisson_min_max_unit(u);
            (e.min, e.min_v)
        });
        let high = search_pairs(&|u, v| -nu(u, v), &|u| {
            let e = self.poisson_min_max_unit(u);
            (-e.max, e.max_v)
        });
        let value = |[u, v]: [[f64; 3]; 2]| nu(u, v);
        pair_extremes(value(low), low, value(high), high)
    }
}

/// The [`PairExtremes`] of two found pairs, ordered by value.
fn pair_extremes(a: f64, a_pair: [[f64; 3]; 2], b: f64, b_pair: [[f64; 3]; 2]) -> PairExtremes {
    let ((min, min_pair), (max, max_pair)) = if a <= b {
        ((a, a_pair), (b, b_pair))
    } else {
        ((b, b_pair), (a, a_pair))
    };
    PairExtremes {
        min,
        max,
        min_pair,
        max_pair,
    }
}

/// `n` nearly evenly spread unit vectors on the half sphere `z > 0` (a Fibonacci
/// lattice: equal-area bands in z, golden-angle steps in azimuth).
pub fn fibonacci_half_sphere(n: usize) -> Vec<[f64; 3]> {
    let golden_angle = std::f64::consts::PI * (3.0 - 5.0_f64.sqrt());
    (0..n)
        .map(|i| {
            let z = (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let (s, c) = (i as f64 * golden_angle).sin_cos();
            [r * c, r * s, z]
        })
        .collect()
}

/// The best-scored (lowest) items, skipping any within [`SEED_SEPARATION`] of one
/// already taken (as lines: `u` and `-u` are the same direction).
fn separated_best<T: Copy>(mut scored: Vec<(f64, [f64; 3], T)>) -> Vec<([f64; 3], T)> {
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    let cos_limit = SEED_SEPARATION.cos();
    let mut taken: Vec<([f64; 3], T)> = Vec::new();
    for (_, u, extra) in scored {
        if taken.iter().all(|(t, _)| dot(*t, u).abs() < cos_limit) {
            taken.push((u, extra));
            if taken.len() == REFINED_SEEDS {
                break;
            }
        }
    }
    taken
}

/// A unit `u` minimising `f` over the sphere (globally, see the module notes).
fn search_sphere(f: &dyn Fn([f64; 3]) -> f64) -> [f64; 3] {
    let scored = fibonacci_half_sphere(SEED_COUNT)
        .into_iter()
        .map(|u| (f(u), u, ()))
        .collect();
    let mut best = ([0.0, 0.0, 1.0], f64::INFINITY);
    for (seed, ()) in separated_best(scored) {
        let found = refine_on_sphere(f, seed);
        if found.1 < best.1 {
            best = found;
        }
    }
    best.0
}

/// A perpendicular unit pair `[u, v]` minimising `f` (globally, see the module
/// notes); `inner(u)` is the exact minimum over `v ⊥ u` and its `v`.
fn search_pairs(
    f: &dyn Fn([f64; 3], [f64; 3]) -> f64,
    inner: &dyn Fn([f64; 3]) -> (f64, [f64; 3]),
) -> [[f64; 3]; 2] {
    let scored = fibonacci_half_sphere(SEED_COUNT)
        .into_iter()
        .map(|u| {
            let (value, v) = inner(u);
            (value, u, v)
        })
        .collect();
    let mut best = ([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], f64::INFINITY);
    for (u, v) in separated_best(scored) {
        let ([u, v], value) = refine_on_pairs(f, u, v);
        // Polish v: the exact optimum over v ⊥ u can only improve on the search's.
        let (inner_value, inner_v) = inner(u);
        let candidate = if inner_value < value {
            ([u, inner_v], inner_value)
        } else {
            ([u, v], value)
        };
        if candidate.1 < best.1 {
            best = candidate;
        }
    }
    best.0
}

/// Local minimum of `f` on the sphere near `seed`, with its value.
///
/// Nelder–Mead in the chart `x ↦ normalise(u0 + x₁e₁ + x₂e₂)` around the current best
/// `u0`, restarted (re-centred, smaller simplex) until a restart gains nothing.
fn refine_on_sphere(f: &dyn Fn([f64; 3]) -> f64, seed: [f64; 3]) -> ([f64; 3], f64) {
    let mut best = (seed, f(seed));
    let mut step = 0.05;
    for _ in 0..MAX_RESTARTS {
        let (e1, e2) = plane_basis(best.0);
        let u0 = best.0;
        let chart =
            |x: &[f64]| normalized(std::array::from_fn(|i| u0[i] + x[0] * e1[i] + x[1] * e2[i]));
        let (x, value) = nelder_mead(&|x| f(chart(x)), &[0.0, 0.0], step);
        let improved = value < best.1;
        if improved {
            best = (chart(&x), value);
        }
        if !improved || step < 1e-7 {
            break;
        }
        step *= 0.1;
    }
    best
}

/// Local minimum of `f` over perpendicular unit pairs near `(u, v)`, with its value.
///
/// Nelder–Mead in the chart `x ↦ (Q(x) u0, Q(x) v0)`, `Q(x)` the rotation by angle
/// `|x|` about `x`, restarted as in [`refine_on_sphere`].
fn refine_on_pairs(
    f: &dyn Fn([f64; 3], [f64; 3]) -> f64,
    u: [f64; 3],
    v: [f64; 3],
) -> ([[f64; 3]; 2], f64) {
    let mut best = ([u, v], f(u, v));
    let mut step = 0.05;
    for _ in 0..MAX_RESTARTS {
        let [u0, v0] = best.0;
        let chart = |x: &[f64]| {
            let axis = [x[0], x[1], x[2]];
            [rodrigues(axis, u0), rodrigues(axis, v0)]
        };
        let (x, value) = nelder_mead(
            &|x| {
                let [a, b] = chart(x);
                f(a, b)
            },
            &[0.0, 0.0, 0.0],
            step,
        );
        let improved = value < best.1;
        if improved {
            let [a, b] = chart(&x);
            // Re-orthonormalise against drift.
            let a = normalized(a);
            let b = normalized(cross(cross(a, b), a));
            best = ([a, b], f(a, b).min(value));
        }
        if !improved || step < 1e-7 {
            break;
        }
        step *= 0.1;
    }
    best
}

/// `p` rotated by angle `|axis|` (radians) about `axis`.
fn rodrigues(axis: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let angle = dot(axis, axis).sqrt();
    if angle == 0.0 {
        return p;
    }
    let k = axis.map(|x| x / angle);
    let (s, c) = angle.sin_cos();
    let k_cross_p = cross(k, p);
    let k_dot_p = dot(k, p);
    std::array::from_fn(|i| p[i] * c + k_cross_p[i] * s + k[i] * k_dot_p * (1.0 - c))
}

/// Restarts of a local refinement at most.
const MAX_RESTARTS: usize = 6;

/// Evaluations of one Nelder–Mead run at most.
const MAX_EVALUATIONS: usize = 4000;

/// A local minimum of `f` from `start` by Nelder–Mead (standard coefficients:
/// reflection 1, expansion 2, contraction 1/2, shrink 1/2), initial simplex of edge
/// `step` along the axes; stops when the simplex is smaller than `1e-9 · step` (the
/// value is then off by the square of that at a smooth minimum), or after
/// [`MAX_EVALUATIONS`].
fn nelder_mead(f: &dyn Fn(&[f64]) -> f64, start: &[f64], step: f64) -> (Vec<f64>, f64) {
    let n = start.len();
    let mut simplex: Vec<(Vec<f64>, f64)> = (0..=n)
        .map(|k| {
            let mut x = start.to_vec();
            if k > 0 {
                x[k - 1] += step;
            }
            let value = f(&x);
            (x, value)
        })
        .collect();
    let mut evaluations = n + 1;
    while evaluations < MAX_EVALUATIONS {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        if simplex_converged(&simplex, step) {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|i| simplex[..n].iter().map(|(x, _)| x[i]).sum::<f64>() / n as f64)
            .collect();
        let worst = simplex[n].clone();
        let towards = |t: f64| -> Vec<f64> {
            (0..n)
                .map(|i| centroid[i] + t * (worst.0[i] - centroid[i]))
                .collect()
        };
        let reflected = towards(-1.0);
        let reflected_value = f(&reflected);
        evaluations += 1;
        if reflected_value < simplex[0].1 {
            let expanded = towards(-2.0);
            let expanded_value = f(&expanded);
            evaluations += 1;
            simplex[n] = if expanded_value < reflected_value {
                (expanded, expanded_value)
            } else {
                (reflected, reflected_value)
            };
        } else if reflected_value < simplex[n - 1].1 {
            simplex[n] = (reflected, reflected_value);
        } else {
            let contracted = if reflected_value < worst.1 {
                towards(-0.5)
            } else {
                towards(0.5)
            };
            let contracted_value = f(&contracted);
            evaluations += 1;
            if contracted_value < worst.1.min(reflected_value) {
                simplex[n] = (contracted, contracted_value);
            } else {
                let best = simplex[0].0.clone();
                for (x, value) in simplex.iter_mut().skip(1) {
                    for i in 0..n {
                        x[i] = best[i] + 0.5 * (x[i] - best[i]);
                    }
                    *value = f(x);
                }
                evaluations += n;
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex.swap_remove(0)
}

/// Whether a sorted simplex has shrunk below `1e-9 · step` along every axis.
fn simplex_converged(simplex: &[(Vec<f64>, f64)], step: f64) -> bool {
    let best = &simplex[0].0;
    simplex
        .iter()
        .flat_map(|(x, _)| x.iter().zip(best).map(|(a, b)| (a - b).abs()))
        .all(|distance| distance < 1e-9 * step)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nelder_mead_finds_a_quadratic_minimum() {
        let f = |x: &[f64]| (x[0] - 0.3).powi(2) + 10.0 * (x[1] + 0.2).powi(2) + 1.0;
        let (x, value) = nelder_mead(&f, &[0.0, 0.0], 0.1);
        assert!(
            (x[0] - 0.3).abs() < 1e-7 && (x[1] + 0.2).abs() < 1e-7,
            "{x:?}"
        );
        assert!((value - 1.0).abs() < 1e-13);
    }

    #[test]
    fn fibonacci_points_are_unit_and_spread() {
        let points = fibonacci_half_sphere(2000);
        assert!(
            points
                .iter()
                .all(|p| (dot(*p, *p) - 1.0).abs() < 1e-14 && p[2] > 0.0)
        );
        // Every direction (either sign) is within 0.06 rad of some point.
        for probe in fibonacci_half_sphere(997) {
            let probe = [probe[1], -probe[2], probe[0]];
            let nearest = points
                .iter()
                .map(|p| dot(*p, probe).abs())
                .fold(0.0, f64::max);
            assert!(nearest > 0.06_f64.cos(), "{probe:?}");
        }
    }

    #[test]
    fn rodrigues_rotates_about_the_axis() {
        let quarter = [0.0, 0.0, std::f64::consts::FRAC_PI_2];
        let r = rodrigues(quarter, [1.0, 0.0, 0.0]);
        assert!((r[0]).abs() < 1e-15 && (r[1] - 1.0).abs() < 1e-15 && r[2].abs() < 1e-15);
    }
}
