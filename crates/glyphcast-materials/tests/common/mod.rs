//! Test crystals and reference computations independent of the crate's tensor code.
//!
//! The references work in Voigt form only: the compliance is inverted here with
//! nalgebra, and every modulus is a bilinear form `xᵀ S y` of Voigt stress vectors
//! (or a strain solved from the stiffness), never the crate's 3x3x3x3 tensor.

#![allow(dead_code)]

use nalgebra::{Matrix6, Vector6};

/// Copper, cubic, GPa at room temperature: C11 = 168.4, C12 = 121.4, C44 = 75.4
/// (C. Kittel, Introduction to Solid State Physics, ch. 3, table of cubic elastic
/// stiffness constants: 1.684, 1.214, 0.754 × 10¹² dyn/cm²).
pub const COPPER: (f64, f64, f64) = (168.4, 121.4, 75.4);

/// A cubic Voigt stiffness.
pub fn cubic(c11: f64, c12: f64, c44: f64) -> [[f64; 6]; 6] {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| match (i < 3, j < 3) {
            (true, true) if i == j => c11,
            (true, true) => c12,
            _ if i == j => c44,
            _ => 0.0,
        })
    })
}

/// Copper's Voigt stiffness.
pub fn copper() -> [[f64; 6]; 6] {
    cubic(COPPER.0, COPPER.1, COPPER.2)
}

/// α-quartz, trigonal (class 32), GPa: C11 = 86.8, C33 = 105.8, C44 = 58.2,
/// C12 = 7.0, C13 = 11.9, C14 = -18.0 (rounded values close to McSkimin,
/// Andreatch & Thurston, J. Appl. Phys. 36, 1624 (1965): 86.74, 107.2, 57.94, 6.99,
/// 11.91, -17.91). The trigonal
/// pattern: C22 = C11, C23 = C13, C55 = C44, C66 = (C11 - C12)/2, C24 = -C14,
/// C56 = C14 (checked by the crystal's 3-fold and 2-fold symmetry in the tests).
pub fn quartz() -> [[f64; 6]; 6] {
    trigonal(86.8, 105.8, 58.2, 7.0, 11.9, -18.0)
}

/// A trigonal (classes 32, 3m, -3m) Voigt stiffness with the 2-fold axis along x1.
pub fn trigonal(c11: f64, c33: f64, c44: f64, c12: f64, c13: f64, c14: f64) -> [[f64; 6]; 6] {
    let mut c = [[0.0; 6]; 6];
    let mut set = |i: usize, j: usize, v: f64| {
        c[i - 1][j - 1] = v;
        c[j - 1][i - 1] = v;
    };
    set(1, 1, c11);
    set(2, 2, c11);
    set(3, 3, c33);
    set(1, 2, c12);
    set(1, 3, c13);
    set(2, 3, c13);
    set(4, 4, c44);
    set(5, 5, c44);
    set(6, 6, (c11 - c12) / 2.0);
    set(1, 4, c14);
    set(2, 4, -c14);
    set(5, 6, c14);
    c
}

/// α-cristobalite (SiO2), tetragonal (P4₁2₁2), GPa: C11 = 59.4, C33 = 42.4,
/// C44 = 67.2, C66 = 25.7, C12 = 3.8, C13 = -4.4. Yeganeh-Haeri, Weidner & Parise,
/// Science 257, 650 (1992), Brillouin spectroscopy; its abstract reports Poisson's
/// ratio down to -0.5 in some directions and -0.16 for the aggregate.
pub fn cristobalite() -> [[f64; 6]; 6] {
    let (c11, c33, c44, c66, c12, c13) = (59.4, 42.4, 67.2, 25.7, 3.8, -4.4);
    [
        [c11, c12, c13, 0.0, 0.0, 0.0],
        [c12, c11, c13, 0.0, 0.0, 0.0],
        [c13, c13, c33, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, c44, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, c44, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, c66],
    ]
}

/// An isotropic Voigt stiffness from the bulk and shear moduli.
pub fn isotropic(k: f64, g: f64) -> [[f64; 6]; 6] {
    let lambda = k - 2.0 * g / 3.0;
    // Isotropy is cubic symmetry with C44 = (C11 - C12)/2.
    cubic(lambda + 2.0 * g, lambda, g)
}

/// The Voigt compliance `C⁻¹`, inverted here (not the crate's).
pub fn inverse(c: &[[f64; 6]; 6]) -> [[f64; 6]; 6] {
    let m = Matrix6::from_fn(|i, j| c[i][j])
        .try_inverse()
        .expect("invertible");
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// The Voigt stress vector of the symmetric tensor `(a⊗b + b⊗a)/2`:
/// `[a1b1, a2b2, a3b3, (a2b3+a3b2)/2, (a1b3+a3b1)/2, (a1b2+a2b1)/2]`.
pub fn stress(a: [f64; 3], b: [f64; 3]) -> [f64; 6] {
    [
        a[0] * b[0],
        a[1] * b[1],
        a[2] * b[2],
        0.5 * (a[1] * b[2] + a[2] * b[1]),
        0.5 * (a[0] * b[2] + a[2] * b[0]),
        0.5 * (a[0] * b[1] + a[1] * b[0]),
    ]
}

/// `xᵀ S y`: the complementary energy form of a Voigt compliance with engineering
/// shear strains, `σ : s : τ` for Voigt stress vectors `x`, `y`.
pub fn form(s: &[[f64; 6]; 6], x: [f64; 6], y: [f64; 6]) -> f64 {
    (0..6)
        .map(|i| (0..6).map(|j| x[i] * s[i][j] * y[j]).sum::<f64>())
        .sum()
}

/// Young's modulus in Voigt form: `1/E = aᵀ S a`, `a = [u1², u2², u3², u2u3, u1u3, u1u2]`.
pub fn young(s: &[[f64; 6]; 6], u: [f64; 3]) -> f64 {
    let a = stress(u, u);
    1.0 / form(s, a, a)
}

/// Shear modulus in Voigt form: `1/G = 4 dᵀ S d`, `d` the stress of `sym(u⊗v)`.
pub fn shear(s: &[[f64; 6]; 6], u: [f64; 3], v: [f64; 3]) -> f64 {
    let d = stress(u, v);
    1.0 / (4.0 * form(s, d, d))
}

/// Poisson's ratio in Voigt form: `-aᵀ S b / aᵀ S a`, `a`, `b` the stresses of `u⊗u`, `v⊗v`.
pub fn poisson(s: &[[f64; 6]; 6], u: [f64; 3], v: [f64; 3]) -> f64 {
    let (a, b) = (stress(u, u), stress(v, v));
    -form(s, a, b) / form(s, a, a)
}

/// Linear compressibility in Voigt form: `aᵀ S [1,1,1,0,0,0]`.
pub fn compressibility(s: &[[f64; 6]; 6], u: [f64; 3]) -> f64 {
    form(s, stress(u, u), [1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
}

/// The strain tensor under Voigt stress `sigma`, solved from the stiffness `C ε = σ`
/// (engineering shear strains in ε's Voigt vector, halved back into the tensor).
pub fn strain(c: &[[f64; 6]; 6], sigma: [f64; 6]) -> [[f64; 3]; 3] {
    let m = Matrix6::from_fn(|i, j| c[i][j]);
    let e = m
        .lu()
        .solve(&Vector6::from_row_slice(&sigma))
        .expect("invertible");
    [
        [e[0], e[5] / 2.0, e[4] / 2.0],
        [e[5] / 2.0, e[1], e[3] / 2.0],
        [e[4] / 2.0, e[3] / 2.0, e[2]],
    ]
}

/// `aᵀ M b` for a 3x3 `M`.
pub fn bilinear(m: &[[f64; 3]; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| (0..3).map(|j| a[i] * m[i][j] * b[j]).sum::<f64>())
        .sum()
}

/// A small deterministic generator (SplitMix64) for test directions.
pub struct Random(u64);

impl Random {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// A uniform number in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniformly distributed unit vector.
    pub fn direction(&mut self) -> [f64; 3] {
        let z = 2.0 * self.uniform() - 1.0;
        let phi = 2.0 * std::f64::consts::PI * self.uniform();
        let r = (1.0 - z * z).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }

    /// A uniformly distributed unit vector perpendicular to unit `u`, and a second
    /// one perpendicular to both (an orthonormal pair spanning the plane ⊥ u).
    pub fn plane(&mut self, u: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let helper = if u[0].abs() < 0.6 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let e1 = normalize(cross(u, helper));
        let e2 = cross(u, e1);
        let angle = 2.0 * std::f64::consts::PI * self.uniform();
        let (s, c) = angle.sin_cos();
        (
            std::array::from_fn(|i| c * e1[i] + s * e2[i]),
            std::array::from_fn(|i| -s * e1[i] + c * e2[i]),
        )
    }
}

/// The cross product.
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a / |a|`.
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a.map(|x| x / n)
}

/// The extremes over unit `v` in the plane spanned by orthonormal `e1`, `e2` of a
/// function `q` that is a quadratic form in `v`, by polarisation
/// (`q(e1+e2) - q(e1) - q(e2) = 2 e1ᵀAe2`) and the 2x2 eigenvalue formula.
pub fn plane_range(q: impl Fn([f64; 3]) -> f64, e1: [f64; 3], e2: [f64; 3]) -> (f64, f64) {
    let (a, c) = (q(e1), q(e2));
    let b = 0.5 * (q(std::array::from_fn(|i| e1[i] + e2[i])) - a - c);
    let mean = 0.5 * (a + c);
    let radius = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    (mean - radius, mean + radius)
}

/// An orthonormal basis of the plane ⊥ unit `u`.
pub fn basis(u: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let helper = if u[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = normalize(cross(u, helper));
    (e1, cross(u, e1))
}

/// Brute-force local polish of a function on the sphere: a 41x41 grid of tangent
/// offsets of half-width `r` around the best point, moved to the grid's best, with
/// `r` halved, 45 times from `r = 0.02` (the last grid step is about 1e-15 rad).
pub fn zoom(f: &dyn Fn([f64; 3]) -> f64, start: [f64; 3]) -> f64 {
    let (mut best, mut value) = (start, f(start));
    let mut r = 0.02;
    for _ in 0..45 {
        let (e1, e2) = basis(best);
        let center = best;
        for i in -20..=20 {
            for j in -20..=20 {
                let (x, y) = (r * i as f64 / 20.0, r * j as f64 / 20.0);
                let u = normalize(std::array::from_fn(|k| center[k] + x * e1[k] + y * e2[k]));
                let candidate = f(u);
                if candidate < value {
                    (best, value) = (u, candidate);
                }
            }
        }
        r *= 0.5;
    }
    value
}

/// The relative difference `|a - b| / |b|`.
pub fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}
