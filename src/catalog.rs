//! The one table of what glyphcast draws: the tensor orders and SH bands it accepts and
//! the ray-casting methods with their shaders. Everything else reads it: `build.rs`
//! includes this file to choose the shader variants it compiles (so a layout has shaders
//! exactly when the readers accept it), and the scene reader, the volume input, `fit`,
//! `bench`, the method parser and the tests take their limits and names from here.
//! Adding an order or a method starts here.
//!
//! The file has no dependencies, so that the build script can include it.

/// Highest order of a symmetric tensor glyph. The exact method's float32 binomials are
/// exact up to this order (`glsl/exact_root.glsl` refuses a higher one when compiled).
pub const MAX_SYMMETRIC_ORDER: u32 = 12;

/// Highest order of a non-symmetric tensor glyph (3^n entries: 81 at order 4).
pub const MAX_NONSYMMETRIC_ORDER: u32 = 4;

/// Highest band L of an SH glyph. SH glyphs are drawn as symmetric tensors of order
/// max(L, 2), so this is [`MAX_SYMMETRIC_ORDER`].
pub const MAX_SH_BAND: u32 = MAX_SYMMETRIC_ORDER;

/// A ray-casting method: its name on the command line and in reports, its shaders, and
/// what it reads besides the coefficients.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RayCastMethod {
    /// `--method` name, and the `Method` variant's name in lower case.
    pub name: &'static str,
    /// Fragment shader in `glsl/` (one variant per tensor layout).
    pub fragment: &'static str,
    /// Compute shader of `--path compute`, where the method has one.
    pub compute: Option<&'static str>,
    /// Whether the shaders bound f over ray segments (interval or affine ranges), which
    /// needs the range functions and the glyph's index in the fragment shader.
    pub uses_ranges: bool,
    /// Whether the method marches at a fixed step (and reads step, refinement and the
    /// centre zone).
    pub marches: bool,
}

/// The ray-casting methods, in the order reports list them.
pub const RAY_CAST_METHODS: [RayCastMethod; 4] = [
    RayCastMethod {
        name: "fixed",
        fragment: "raycast_fixed.frag",
        compute: None,
        uses_ranges: false,
        marches: true,
    },
    RayCastMethod {
        name: "interval",
        fragment: "raycast_interval.frag",
        compute: None,
        uses_ranges: true,
        marches: false,
    },
    RayCastMethod {
        name: "affine",
        fragment: "raycast_affine.frag",
        compute: None,
        uses_ranges: true,
        marches: false,
    },
    RayCastMethod {
        name: "exact",
        fragment: "raycast_exact.frag",
        compute: Some("raycast_exact.comp"),
        uses_ranges: false,
        marches: false,
    },
];

/// The closed-form ray/quadric intersection of the diffusion-tensor ellipsoid
/// (`--glyph ellipsoid`, `src/glyph/ellipsoid.rs`): not a `--method` but the shader every
/// ellipsoid glyph set is drawn with, compiled for the symmetric layout of order
/// [`ELLIPSOID_ORDER`] only.
pub const ELLIPSOID_METHOD: RayCastMethod = RayCastMethod {
    name: "ellipsoid",
    fragment: "raycast_ellipsoid.frag",
    compute: None,
    uses_ranges: false,
    marches: false,
};

/// The order of the symmetric tensors that have an ellipsoid (DTI).
pub const ELLIPSOID_ORDER: u32 = 2;

/// The highest tensor order of a layout: [`MAX_SYMMETRIC_ORDER`] or
/// [`MAX_NONSYMMETRIC_ORDER`].
pub const fn max_order(symmetric: bool) -> u32 {
    if symmetric {
        MAX_SYMMETRIC_ORDER
    } else {
        MAX_NONSYMMETRIC_ORDER
    }
}
