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

impl Stiffness {
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
