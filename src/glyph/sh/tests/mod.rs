//! Tests of the SH module against formulas written independently of the code: textbook
//! closed forms and an explicit-sum Legendre function (`closed_forms`), polynomial
//! evaluation of the tensors (`tensor`), function values of converted and rotated
//! series (`convert_rotate`) and direct solves of the fit (`fit`).
use glam::{DMat3, DQuat, DVec3};

use crate::glyph::sh::ShBasis;

mod closed_forms;
mod convert_rotate;
mod evaluator;
mod fit;
mod tensor;

/// Every (basis, legacy) combination of the scene format.
const ALL_BASES: [(ShBasis, bool); 4] = [
    (ShBasis::Tournier07, false),
    (ShBasis::Tournier07, true),
    (ShBasis::Descoteaux07, false),
    (ShBasis::Descoteaux07, true),
];

/// A small deterministic generator (SplitMix64), so failures reproduce.
struct Rng(crate::rng::SplitMix64);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(crate::rng::SplitMix64::new(seed))
    }

    /// Uniform in [-1, 1).
    fn signed(&mut self) -> f64 {
        2.0 * self.0.unit() - 1.0
    }

    fn coefficients(&mut self, n: usize) -> Vec<f64> {
        (0..n).map(|_| self.signed()).collect()
    }

    /// A direction uniform on the sphere (rejection from the cube).
    fn direction(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.signed(), self.signed(), self.signed());
            let len2 = v.length_squared();
            if len2 > 1e-4 && len2 <= 1.0 {
                return v / len2.sqrt();
            }
        }
    }

    fn rotation(&mut self) -> DMat3 {
        let q = DQuat::from_xyzw(self.signed(), self.signed(), self.signed(), self.signed());
        DMat3::from_quat(q.normalize())
    }

    /// A random rotation composed with the reflection through a random plane (det -1).
    fn reflection(&mut self) -> DMat3 {
        let n = self.direction();
        let householder = DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * n.x, n * n.y, n * n.z);
        householder * self.rotation()
    }
}

/// Directions that include the poles, the equator and random ones.
fn test_directions(rng: &mut Rng, random: usize) -> Vec<DVec3> {
    let mut dirs = vec![
        DVec3::Z,
        -DVec3::Z,
        DVec3::X,
        DVec3::new(0.0, -1.0, 1e-9).normalize(),
    ];
    dirs.extend((0..random).map(|_| rng.direction()));
    dirs
}
