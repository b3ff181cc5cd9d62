//! Voigt, Reuss and Hill averages of the bulk and shear moduli of a polycrystal.

use serde::{Deserialize, Serialize};

use crate::stiffness::Stiffness;

/// One modulus averaged three ways.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Vrh {
    /// Voigt's average (uniform strain): an upper bound.
    pub voigt: f64,
    /// Reuss's average (uniform stress): a lower bound.
    pub reuss: f64,
    /// Hill's average: the mean of the two.
    pub hill: f64,
}

impl Vrh {
    /// The triple with `hill` the mean of `voigt` and `reuss`.
    fn new(voigt: f64, reuss: f64) -> Self {
        Self {
            voigt,
            reuss,
            hill: 0.5 * (voigt + reuss),
        }
    }
}

/// The bulk and shear moduli of a random polycrystal, averaged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Averages {
    /// Bulk modulus `K`.
    pub bulk: Vrh,
    /// Shear modulus `G`.
    pub shear: Vrh,
}

impl Stiffness {
    /// The Voigt, Reuss and Hill bulk and shear moduli:
    ///
    /// - `K_V = ((C11+C22+C33) + 2(C12+C23+C31)) / 9`
    /// - `G_V = ((C11+C22+C33) - (C12+C23+C31) + 3(C44+C55+C66)) / 15`
    /// - `K_R = 1 / ((S11+S22+S33) + 2(S12+S23+S31))`
    /// - `G_R = 15 / (4(S11+S22+S33) - 4(S12+S23+S31) + 3(S44+S55+S66))`
    /// - Hill: the mean of Voigt and Reuss.
    pub fn averages(&self) -> Averages {
        let (c_normal, c_cross, c_shear) = trace_sums(self.voigt());
        let (s_normal, s_cross, s_shear) = trace_sums(self.compliance());
        let bulk_voigt = (c_normal + 2.0 * c_cross) / 9.0;
        let shear_voigt = (c_normal - c_cross + 3.0 * c_shear) / 15.0;
        let bulk_reuss = 1.0 / (s_normal + 2.0 * s_cross);
        let shear_reuss = 15.0 / (4.0 * s_normal - 4.0 * s_cross + 3.0 * s_shear);
        Averages {
            bulk: Vrh::new(bulk_voigt, bulk_reuss),
            shear: Vrh::new(shear_voigt, shear_reuss),
        }
    }
}

/// `(M11+M22+M33, M12+M23+M31, M44+M55+M66)` of a Voigt matrix.
fn trace_sums(m: &[[f64; 6]; 6]) -> (f64, f64, f64) {
    (
        m[0][0] + m[1][1] + m[2][2],
        m[0][1] + m[1][2] + m[2][0],
        m[3][3] + m[4][4] + m[5][5],
    )
}
