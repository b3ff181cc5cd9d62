//! Directional elastic properties of anisotropic crystals, in float64, from a 6x6
//! stiffness matrix in Voigt notation (ELATE's quantities).
//!
//! # Conventions
//!
//! **Voigt notation.** Index `m = 1…6` stands for the tensor index pairs 11, 22, 33,
//! 23, 13, 12. The stiffness is `C_ijkl = C_mn`. The compliance `S = C⁻¹` uses
//! engineering shear strains (`S44 = 1/G` for an isotropic solid), so its tensor is
//! `s_ijkl = S_mn · w_m · w_n` with `w = 1` for `m ≤ 3` and `w = 1/2` for `m > 3`
//! (factor 1, 1/2 or 1/4). Values keep the input's units (e.g. GPa); compressibilities
//! are in the inverse units.
//!
//! **Input.** [`Stiffness::new`] refuses a non-finite entry, a matrix with
//! `|C_ij - C_ji| > 1e-6 · max|C|` (naming the pair), and one that is not positive
//! definite (mechanically unstable; the error carries the smallest eigenvalue) unless
//! [`Options::allow_unstable`] is set, when only a singular matrix is refused.
//!
//! **Directional moduli** for unit `u` and unit `v ⊥ u`:
//!
//! - Young's modulus `1/E(u) = Σ s_ijkl u_i u_j u_k u_l`. In Voigt form this is
//!   `aᵀ S a` with `a = [u1², u2², u3², u2u3, u1u3, u1u2]`: the shear entries need no
//!   factor 2, because each Voigt shear index collects two tensor index pairs (×2)
//!   whose compliance entries carry a factor 1/2 (cubic check:
//!   `1/E = S11 - 2(S11 - S12 - S44/2)(u1²u2² + u2²u3² + u3²u1²)`).
//! - Linear compressibility `β(u) = Σ s_ijkk u_i u_j` (negative: expands along `u`
//!   under hydrostatic pressure).
//! - Shear modulus `1/G(u, v) = 4 Σ s_ijkl u_i v_j u_k v_l`.
//! - Poisson's ratio `ν(u, v) = -Σ s_ijkl u_i u_j v_k v_l / Σ s_ijkl u_i u_j u_k u_l`.
//!
//! For fixed `u`, `1/G` and the numerator of `ν` are quadratic forms in `v`, so their
//! extremes over the plane ⊥ `u` are the eigenvalues of a 2x2 symmetric matrix:
//! [`Stiffness::shear_min_max`] and [`Stiffness::poisson_min_max`] are exact.
//!
//! **Global extremes** ([`Stiffness::summary`]): `β`'s are the extreme eigenvalues of
//! `β_ij = Σ_k s_ijkk`, exactly. Those of `E`, `G` (min over `u` of `Gmin(u)`, max
//! over `u` of `Gmax(u)`) and `ν` are searched: the [`SEED_COUNT`] directions of a
//! Fibonacci half sphere ([`fibonacci_half_sphere`]; all the moduli are even in `u`)
//! are scored, for `G` and `ν` with their exact extremes over `v ⊥ u`; the
//! [`REFINED_SEEDS`] best scores at least [`SEED_SEPARATION`] apart are refined by
//! Nelder–Mead, over the sphere for `E` and over orthonormal pairs `(u, v)` for `G`
//! and `ν` (smooth there even where the two extremes over `v` cross), restarted
//! until a restart gains nothing. The values reported are re-evaluated at the
//! directions reported. The tests hold them to 1e-9 relative of closed forms and of a
//! polished 200 000-direction sampling.
//!
//! **Averages**: Voigt, Reuss and Hill bulk and shear moduli ([`Stiffness::averages`]).
//!
//! **Orientation.** A [`Rotation`] `g` maps sample coordinates to crystal coordinates,
//! `x_crystal = g · x_sample`. Bunge Euler angles `(φ1, Φ, φ2)` in degrees give
//! `g = Rz(φ2) Rx(Φ) Rz(φ1)` with the passive matrices of texture analysis,
//! `Rz(φ) = [[cos φ, sin φ, 0], [-sin φ, cos φ, 0], [0, 0, 1]]` and
//! `Rx(Φ) = [[1, 0, 0], [0, cos Φ, sin Φ], [0, -sin Φ, cos Φ]]` (as MTEX). The sample-
//! frame tensor is `C'_ijkl = g_mi g_nj g_ok g_pl C_mnop` ([`rotate`],
//! [`Stiffness::rotated`]), so that `E'(u) = E(g u)`.
//!
//! **Surfaces for drawing**: [`Stiffness::radius`] for each [`Surface`], the compliance
//! quartic's coefficients [`Stiffness::compliance_tensor`], and for the surfaces that are
//! tensor glyphs (Young's modulus, the reciprocal glyph of the compliance quartic; linear
//! compressibility, the glyph of `β_ij`) their forms [`Stiffness::surface_form`], with
//! [`Stiffness::largest_radius`] to put several materials on one scale.

//! # Example
//!
//! ```
//! use glyphcast_materials::Stiffness;
//!
//! let (c11, c12, c44) = (168.4, 121.4, 75.4); // copper, GPa
//! let copper = [
//!     [c11, c12, c12, 0.0, 0.0, 0.0],
//!     [c12, c11, c12, 0.0, 0.0, 0.0],
//!     [c12, c12, c11, 0.0, 0.0, 0.0],
//!     [0.0, 0.0, 0.0, c44, 0.0, 0.0],
//!     [0.0, 0.0, 0.0, 0.0, c44, 0.0],
//!     [0.0, 0.0, 0.0, 0.0, 0.0, c44],
//! ];
//! let stiffness = Stiffness::new(copper)?;
//! let e100 = stiffness.young([1.0, 0.0, 0.0])?;
//! let summary = stiffness.summary();
//! assert!((summary.young.min - e100).abs() < 1e-9 * e100);
//! println!("{}", summary.to_table("GPa"));
//! # Ok::<(), glyphcast_materials::Error>(())
//! ```

#![warn(missing_docs)]

mod averages;
mod error;
mod extremes;
mod rotation;
mod stiffness;
mod summary;
mod surface;
mod voigt;

pub use averages::{Averages, Vrh};
pub use error::{Error, RotationDefect};
pub use extremes::{
    DirectionalExtremes, PairExtremes, REFINED_SEEDS, SEED_COUNT, SEED_SEPARATION,
    fibonacci_half_sphere,
};
pub use rotation::{ROTATION_TOLERANCE, Rotation, bond_matrix, rotate, rotate_tensor};
pub use stiffness::{
    Options, PERPENDICULAR_TOLERANCE, PlaneExtremes, SYMMETRY_TOLERANCE, Stiffness,
};
pub use summary::{MinMax, Summary};
pub use surface::{PlaneForms, PoissonForms, RatioForms, Surface, SurfaceForm};
pub use voigt::{Kind, Tensor4, VOIGT_PAIRS, Voigt, contract, from_tensor, to_tensor, voigt_index};
