//! The directional surfaces a renderer draws: one radius per direction.

use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::stiffness::{Stiffness, unit};

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
    /// every pair, which bounds them.
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

    /// The forms evaluate to 1/E and β at random directions (to 1e-12), the shear and
    /// Poisson surfaces have none, and the largest radii are the summary's extremes.
    #[test]
    fn surface_forms_are_the_moduli() {
        // Quartz (trigonal), GPa: C11, C33, C44, C12, C13, C14.
        let (c11, c33, c44, c12, c13, c14) = (86.8, 105.8, 58.2, 7.0, 11.9, -18.0);
        let c66 = (c11 - c12) / 2.0;
        let quartz = Stiffness::new([
            [c11, c12, c13, c14, 0.0, 0.0],
            [c12, c11, c13, -c14, 0.0, 0.0],
            [c13, c13, c33, 0.0, 0.0, 0.0],
            [c14, -c14, 0.0, c44, 0.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, c44, c14],
            [0.0, 0.0, 0.0, 0.0, c14, c66],
        ])
        .unwrap();
        let form_at = |form: &SurfaceForm, u: [f64; 3]| -> f64 {
            let n = form.order as usize;
            (0..form.tensor.len())
                .map(|flat| {
                    let product: f64 = (0..n)
                        .map(|k| u[flat / 3usize.pow((n - 1 - k) as u32) % 3])
                        .product();
                    form.tensor[flat] * product
                })
                .sum()
        };
        let young = quartz.surface_form(Surface::Young).unwrap();
        let beta = quartz.surface_form(Surface::Compressibility).unwrap();
        assert!(young.reciprocal && !beta.reciprocal);
        assert_eq!((young.order, beta.order), (4, 2));
        for u in crate::fibonacci_half_sphere(50) {
            let e = quartz.radius(Surface::Young, u).unwrap();
            assert!((form_at(&young, u) * e - 1.0).abs() < 1e-12);
            let b = quartz.radius(Surface::Compressibility, u).unwrap();
            assert!((form_at(&beta, u) - b).abs() < 1e-12 * b.abs().max(1e-3));
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
}
