//! The directional surfaces a renderer draws: one radius per direction.

use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::stiffness::{Stiffness, unit};
use crate::voigt::Tensor4;

/// A directional surface: the radius along `u` is a modulus of direction `u`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Surface {
    /// Young's modulus `E(u)`.
    Young,
    /// Linear compressibility `β(u)` (negative where the crystal expands under pressure).
    Compressibility,
    /// The smallest shear modulus over `v ⊥ u`.
    ShearMin,
    /// The largest shear modulus over `v ⊥ u`.
    ShearMax,
    /// The smallest Poisson's ratio over `v ⊥ u`.
    PoissonMin,
    /// The largest Poisson's ratio over `v ⊥ u`.
    PoissonMax,
}

impl Surface {
    /// All six surfaces.
    pub const ALL: [Surface; 6] = [
        Surface::Young,
        Surface::Compressibility,
        Surface::ShearMin,
        Surface::ShearMax,
        Surface::PoissonMin,
        Surface::PoissonMax,
    ];
}

impl Surface {
    /// The name the command line and Python take: `young`, `compressibility`,
    /// `shear-min`, `shear-max`, `poisson-min`, `poisson-max`.
    pub fn name(self) -> &'static str {
        match self {
            Surface::Young => "young",
            Surface::Compressibility => "compressibility",
            Surface::ShearMin => "shear-min",
            Surface::ShearMax => "shear-max",
            Surface::PoissonMin => "poisson-min",
            Surface::PoissonMax => "poisson-max",
        }
    }

    /// The surface of a [`Surface::name`].
    pub fn from_name(name: &str) -> Option<Surface> {
        Surface::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// A surface that is the glyph of a tensor form: radius `|f(u)|`, or `1/|f(u)|` where
/// `reciprocal`, with `f(u) = Σ tensor[i1..in] u_i1 … u_in`.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceForm {
    /// The order n of the form.
    pub order: u32,
    /// All `3^n` entries, row-major (the last index fastest).
    pub tensor: Vec<f64>,
    /// Whether the radius is `1/|f|` (Young's modulus: `f` is `1/E`).
    pub reciprocal: bool,
}

/// The two forms whose roots are a surface's radii where no single form is: for unit
/// `u`, the extremes over `v ⊥ u` of a quadratic form `vᵀ A(u) v` (with `A(u)`'s
/// entries quadratic in `u`) are the two eigenvalues `λ` of `A(u)` on the plane ⊥ `u`,
/// the roots of `λ² − T(u) λ + D(u) = 0`, with `T` the trace of that 2x2 restriction
/// and `D` its determinant. Written as forms of `u` of any length,
/// `T(u) = tr A(u) |u|² − uᵀ A(u) u` (order 4) and `D(u) = uᵀ adj A(u) u` (order 6),
/// which are the trace and determinant at unit `u`.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneForms {
    /// `T`: all `3^4` entries, row-major (the last index fastest).
    pub trace: Vec<f64>,
    /// `D`: all `3^6` entries, row-major.
    pub determinant: Vec<f64>,
    /// Whether the surface's radius is `1/λ` of the larger root (`true`: the smallest
    /// shear modulus) or of the smaller.
    pub larger_root: bool,
}

impl PlaneForms {
    /// The forms of the quadratic forms `vᵀ A(u) v`, `A_jl(u) = Σ m[j][l][i][k] u_i u_k`.
    fn of(m: &Tensor4, larger_root: bool) -> PlaneForms {
        let mut trace = vec![0.0; 81];
        let at4 = |i: usize, j: usize, k: usize, l: usize| 27 * i + 9 * j + 3 * k + l;
        for i in 0..3 {
            for k in 0..3 {
                for j in 0..3 {
                    for a in 0..3 {
                        // tr A(u) |u|²
                        trace[at4(i, k, a, a)] += m[j][j][i][k];
                        // − uᵀ A(u) u
                        trace[at4(i, k, j, a)] -= m[j][a][i][k];
                    }
                }
            }
        }
        // uᵀ adj(A) u = ½ ε_aij ε_bkl A_ik A_jl u_a u_b (the cofactors of a symmetric A).
        let epsilon = |a: usize, b: usize, c: usize| -> f64 {
            match (a, b, c) {
                (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
                (0, 2, 1) | (2, 1, 0) | (1, 0, 2) => -1.0,
                _ => 0.0,
            }
        };
        let mut determinant = vec![0.0; 729];
        for a in 0..3 {
            for b in 0..3 {
                for (i, j, k, l) in (0..81).map(|n| (n / 27, n / 9 % 3, n / 3 % 3, n % 3)) {
                    let sign = epsilon(a, i, j) * epsilon(b, k, l);
                    if sign == 0.0 {
                        continue;
                    }
                    for p in 0..81 {
                        let (p1, p2, p3, p4) = (p / 27, p / 9 % 3, p / 3 % 3, p % 3);
                        let flat = 243 * a + 81 * b + 27 * p1 + 9 * p2 + 3 * p3 + p4;
                        determinant[flat] += 0.5 * sign * m[i][k][p1][p2] * m[j][l][p3][p4];
                    }
                }
            }
        }
        PlaneForms {
            trace,
            determinant,
            larger_root,
        }
    }
}

impl Stiffness {
    /// The forms of the shear surfaces (`shear-min`: the larger root of `1/G`,
    /// `shear-max`: the smaller), in the inverse of the input's units: `1/G(u, v) =
    /// vᵀ A(u) v` with `A_jl(u) = 4 Σ s_ijkl u_i u_k`. `None` for the other surfaces.
    pub fn plane_forms(&self, surface: Surface) -> Option<PlaneForms> {
        let larger_root = match surface {
            Surface::ShearMin => true,
            Surface::ShearMax => false,
            _ => return None,
        };
        let s = self.compliance_tensor();
        let m: Tensor4 = std::array::from_fn(|j| {
            std::array::from_fn(|l| {
                std::array::from_fn(|i| std::array::from_fn(|k| 4.0 * s[i][j][k][l]))
            })
        });
        Some(PlaneForms::of(&m, larger_root))
    }
}

/// The forms of the Poisson's ratio surfaces. At unit `u`, `ν(u, v)` over `v ⊥ u`
/// ranges between `−λ/Q(u)` for the two roots `λ` of `λ² − T(u) λ + D(u) = 0`, where `T`
/// and `D` (`plane`) are the trace and determinant forms of the numerator `s(u, u, v, v)`
/// restricted to the plane ⊥ `u`, and `Q(u) = s(u, u, u, u) = 1/E(u)` (`young`, order
/// 4). A point `q = |ν| u` of a surface, `ν = σ |q|` (`σ` its sign), satisfies
/// `|q| (Q(q)² + D(q)) = −σ Q(q) T(q)`, so every surface point is a root of
/// `|q|² (Q(q)² + D(q))² − Q(q)² T(q)²`, of degree 18 along a ray; the root is on the
/// branch of the larger `λ` where `−2 σ |q| Q(q) ≥ T(q)`. For a stable crystal (`Q > 0`)
/// the smallest ratio, `poisson-min`, takes the larger `λ` (`plane.larger_root`).
#[derive(Debug, Clone, PartialEq)]
pub struct PoissonForms {
    /// `Q = 1/E`: all `3^4` entries, row-major (the last index fastest).
    pub young: Vec<f64>,
    /// `T` and `D` of the numerator, and which root the surface takes.
    pub plane: PlaneForms,
}

impl Stiffness {
    /// The forms of the Poisson's ratio surfaces (`poisson-min`: the larger root `λ`,
    /// `poisson-max`: the smaller; [`PoissonForms`]), dimensionless. `None` for the
    /// other surfaces.
    pub fn poisson_forms(&self, surface: Surface) -> Option<PoissonForms> {
        let larger_root = match surface {
            Surface::PoissonMin => true,
            Surface::PoissonMax => false,
            _ => return None,
        };
        let s = self.compliance_tensor();
        // The numerator vᵀ A(u) v = s(u, u, v, v): A_kl(u) = Σ s_ijkl u_i u_j.
        let m: Tensor4 = std::array::from_fn(|k| {
            std::array::from_fn(|l| std::array::from_fn(|i| std::array::from_fn(|j| s[i][j][k][l])))
        });
        Some(PoissonForms {
            young: s.iter().flatten().flatten().flatten().copied().collect(),
            plane: PlaneForms::of(&m, larger_root),
        })
    }
}

/// The forms of a ratio surface r(u) = λ(u) / Q(u), with λ a root of
/// `λ² − T(u) λ + D(u) = 0`: what a renderer's ratio glyph (shape `ratio-min` or
/// `ratio-max`) draws, as |r| coloured by its sign. Poisson's ratio is `−λ'/Q` for the
/// numerator's roots `λ'` ([`PoissonForms`]), so its `λ = −λ'` are the roots with `T`
/// negated, and its smallest ratio takes the smaller of them.
#[derive(Debug, Clone, PartialEq)]
pub struct RatioForms {
    /// `D`: all `3^6` entries, row-major (the last index fastest).
    pub determinant: Vec<f64>,
    /// `T`: all `3^4` entries, row-major.
    pub trace: Vec<f64>,
    /// `Q`, positive for a stable crystal: all `3^4` entries, row-major.
    pub denominator: Vec<f64>,
    /// Whether the surface takes the smaller root `λ` (the smallest ratio, as `Q > 0`).
    pub smaller_root: bool,
}

impl Stiffness {
    /// The ratio forms of the Poisson's ratio surfaces ([`RatioForms`]), dimensionless;
    /// `None` for the other surfaces.
    pub fn ratio_forms(&self, surface: Surface) -> Option<RatioForms> {
        let forms = self.poisson_forms(surface)?;
        Some(RatioForms {
            determinant: forms.plane.determinant,
            trace: forms.plane.trace.iter().map(|t| -t).collect(),
            denominator: forms.young,
            smaller_root: forms.plane.larger_root,
        })
    }
}

impl Stiffness {
    /// The tensor form whose glyph is `surface`, where there is one: Young's modulus is
    /// the reciprocal glyph of the compliance quartic `s_ijkl` (`1/E(u) = s(u,u,u,u)`),
    /// linear compressibility the glyph of the quadratic form `β_ij = Σ_k s_ijkk`. The
    /// extremes of shear modulus and Poisson's ratio over `v ⊥ u` are no polynomial
    /// forms of `u`: `None`.
    pub fn surface_form(&self, surface: Surface) -> Option<SurfaceForm> {
        match surface {
            Surface::Young => Some(SurfaceForm {
                order: 4,
                tensor: self
                    .compliance_tensor()
                    .iter()
                    .flatten()
                    .flatten()
                    .flatten()
                    .copied()
                    .collect(),
                reciprocal: true,
            }),
            Surface::Compressibility => Some(SurfaceForm {
                order: 2,
                tensor: self
                    .compressibility_matrix()
                    .iter()
                    .flatten()
                    .copied()
                    .collect(),
                reciprocal: false,
            }),
            _ => None,
        }
    }

    /// The largest `|radius|` of `surface` over all directions (for sizing several
    /// materials on one scale): Young's largest modulus, the largest `|β|` (exact
    /// eigenvalues), and for the extremes over `v ⊥ u` the largest `|G|` or `|ν|` over
    /// every pair, which bounds them: a material's smallest and largest surfaces are
    /// drawn on one scale, as ELATE plots them.
    pub fn largest_radius(&self, surface: Surface) -> f64 {
        let largest = |min: f64, max: f64| min.abs().max(max.abs());
        match surface {
            Surface::Young => {
                let e = self.young_extremes();
                largest(e.min, e.max)
            }
            Surface::Compressibility => {
                let b = self.compressibility_extremes();
                largest(b.min, b.max)
            }
            Surface::ShearMin | Surface::ShearMax => {
                let g = self.shear_extremes();
                largest(g.min, g.max)
            }
            Surface::PoissonMin | Surface::PoissonMax => {
                let p = self.poisson_extremes();
                largest(p.min, p.max)
            }
        }
    }

    /// The signed radius of `surface` along `u` (any nonzero length): the modulus
    /// itself, in the input's units (inverse units for compressibility). A renderer
    /// draws `|radius|` and colours the sign.
    pub fn radius(&self, surface: Surface, u: [f64; 3]) -> Result<f64, Error> {
        let u = unit(u, "u")?;
        Ok(match surface {
            Surface::Young => 1.0 / self.inverse_young_unit(u),
            Surface::Compressibility => self.linear_compressibility(u)?,
            Surface::ShearMin => self.shear_min_max_unit(u).min,
            Surface::ShearMax => self.shear_min_max_unit(u).max,
            Surface::PoissonMin => self.poisson_min_max_unit(u).min,
            Surface::PoissonMax => self.poisson_min_max_unit(u).max,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The form of order `n` (all `3^n` entries, row-major) at `u`.
    fn form_at(tensor: &[f64], n: usize, u: [f64; 3]) -> f64 {
        (0..tensor.len())
            .map(|flat| {
                let product: f64 = (0..n)
                    .map(|k| u[flat / 3usize.pow((n - 1 - k) as u32) % 3])
                    .product();
                tensor[flat] * product
            })
            .sum()
    }

    /// α-quartz (trigonal, GPa): C11, C33, C44, C12, C13, C14.
    fn quartz() -> Stiffness {
        let (c11, c33, c44, c12, c13, c14) = (86.8, 105.8, 58.2, 7.0, 11.9, -18.0);
        let c66 = (c11 - c12) / 2.0;
        Stiffness::new([
            [c11, c12, c13, c14, 0.0, 0.0],
            [c12, c11, c13, -c14, 0.0, 0.0],
            [c13, c13, c33, 0.0, 0.0, 0.0],
            [c14, -c14, 0.0, c44, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, c44, c14],
            [0.0, 0.0, 0.0, 0.0, c14, c66],
        ])
        .unwrap()
    }

    /// Copper (cubic, GPa) turned by Bunge angles 10, 20, 30 degrees.
    fn turned_copper() -> Stiffness {
        let (c11, c12, c44) = (168.4, 121.4, 75.4);
        Stiffness::new([
            [c11, c12, c12, 0.0, 0.0, 0.0],
            [c12, c11, c12, 0.0, 0.0, 0.0],
            [c12, c12, c11, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, c44, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, c44, 0.0],
            [0.0, 0.0, 0.0, 0.0, 0.0, c44],
        ])
        .unwrap()
        .rotated(&crate::Rotation::from_bunge_degrees(10.0, 20.0, 30.0).unwrap())
    }

    /// The forms evaluate to 1/E and β at random directions (to 1e-12), the shear and
    /// Poisson surfaces have none, and the largest radii are the summary's extremes.
    #[test]
    fn surface_forms_are_the_moduli() {
        let quartz = quartz();
        let young = quartz.surface_form(Surface::Young).unwrap();
        let beta = quartz.surface_form(Surface::Compressibility).unwrap();
        assert!(young.reciprocal && !beta.reciprocal);
        assert_eq!((young.order, beta.order), (4, 2));
        for u in crate::fibonacci_half_sphere(50) {
            let e = quartz.radius(Surface::Young, u).unwrap();
            assert!((form_at(&young.tensor, 4, u) * e - 1.0).abs() < 1e-12);
            let b = quartz.radius(Surface::Compressibility, u).unwrap();
            assert!((form_at(&beta.tensor, 2, u) - b).abs() < 1e-12 * b.abs().max(1e-3));
        }
        for s in [
            Surface::ShearMin,
            Surface::ShearMax,
            Surface::PoissonMin,
            Surface::PoissonMax,
        ] {
            assert!(quartz.surface_form(s).is_none());
        }
        let summary = quartz.summary();
        assert_eq!(quartz.largest_radius(Surface::Young), summary.young.max);
        let b = summary.linear_compressibility;
        assert_eq!(
            quartz.largest_radius(Surface::Compressibility),
            b.min.abs().max(b.max.abs())
        );
        for s in Surface::ALL {
            assert_eq!(Surface::from_name(s.name()), Some(s));
        }
    }

    /// The roots of λ² − T λ + D at random directions are 1/G of the exact 2x2
    /// eigenproblem (`Stiffness::radius`), to 1e-12, on a turned cubic crystal.
    #[test]
    fn plane_forms_give_the_shear_extremes() {
        let copper = turned_copper();
        for (surface, larger) in [(Surface::ShearMin, true), (Surface::ShearMax, false)] {
            let forms = copper.plane_forms(surface).unwrap();
            assert_eq!(forms.larger_root, larger);
            for u in crate::fibonacci_half_sphere(60) {
                let t = form_at(&forms.trace, 4, u);
                let d = form_at(&forms.determinant, 6, u);
                let root = (t * t - 4.0 * d).max(0.0).sqrt();
                let lambda = if larger {
                    (t + root) / 2.0
                } else {
                    (t - root) / 2.0
                };
                let g = copper.radius(surface, u).unwrap();
                assert!(
                    (lambda * g - 1.0).abs() < 1e-12,
                    "{surface:?} {u:?}: {lambda} {g}"
                );
            }
        }
        assert!(copper.plane_forms(Surface::Young).is_none());
    }

    /// `−λ/Q` of the Poisson forms is the exact extreme (`Stiffness::radius`) to 1e-12 at
    /// random directions, every surface point is a root of the degree-18 implicit form,
    /// and the branch test picks the surface's root: on a trigonal crystal, an auxetic
    /// tetragonal one (negative ratios) and a turned cubic one.
    #[test]
    fn poisson_forms_give_the_poisson_extremes() {
        let cristobalite = [
            [59.4, 3.8, -4.4, 0.0, 0.0, 0.0],
            [3.8, 59.4, -4.4, 0.0, 0.0, 0.0],
            [-4.4, -4.4, 42.4, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 67.2, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, 67.2, 0.0],
            [0.0, 0.0, 0.0, 0.0, 0.0, 25.7],
        ];
        let copper = turned_copper();
        let mut negative = 0;
        for crystal in [quartz(), Stiffness::new(cristobalite).unwrap(), copper] {
            for (surface, larger) in [(Surface::PoissonMin, true), (Surface::PoissonMax, false)] {
                let forms = crystal.poisson_forms(surface).unwrap();
                assert_eq!(forms.plane.larger_root, larger);
                for u in crate::fibonacci_half_sphere(60) {
                    let (q, t, d) = (
                        form_at(&forms.young, 4, u),
                        form_at(&forms.plane.trace, 4, u),
                        form_at(&forms.plane.determinant, 6, u),
                    );
                    let root = (t * t - 4.0 * d).max(0.0).sqrt();
                    let lambda = if larger {
                        (t + root) / 2.0
                    } else {
                        (t - root) / 2.0
                    };
                    let nu = crystal.radius(surface, u).unwrap();
                    assert!((-lambda / q - nu).abs() < 1e-12, "{surface:?} {u:?}");
                    // The ratio forms: the root of λ² − T λ + D on their side, over Q.
                    let ratio = crystal.ratio_forms(surface).unwrap();
                    let t = form_at(&ratio.trace, 4, u);
                    let root = (t * t - 4.0 * d).max(0.0).sqrt();
                    let lambda = if ratio.smaller_root {
                        (t - root) / 2.0
                    } else {
                        (t + root) / 2.0
                    };
                    let q = form_at(&ratio.denominator, 4, u);
                    assert!((lambda / q - nu).abs() < 1e-12, "{surface:?} {u:?}");
                    negative += usize::from(nu < 0.0);
                    // The point |ν| u: a root of the implicit form, on its branch.
                    let p = u.map(|x| x * nu.abs());
                    let r = nu.abs();
                    let (qp, tp, dp) = (
                        form_at(&forms.young, 4, p),
                        form_at(&forms.plane.trace, 4, p),
                        form_at(&forms.plane.determinant, 6, p),
                    );
                    let left = r * r * (qp * qp + dp).powi(2);
                    let right = qp * qp * tp * tp;
                    assert!((left - right).abs() <= 1e-9 * (left + right), "{u:?}");
                    let sigma = nu.signum();
                    let side = -2.0 * sigma * r * qp - tp;
                    let tolerance = 1e-9 * (2.0 * r * qp.abs() + tp.abs());
                    if larger {
                        assert!(side >= -tolerance, "{surface:?} {u:?}: {side}");
                    } else {
                        assert!(side <= tolerance, "{surface:?} {u:?}: {side}");
                    }
                }
            }
        }
        // The auxetic crystal's smallest ratios are negative.
        assert!(negative > 0);
        assert!(quartz().poisson_forms(Surface::Young).is_none());
    }
}
