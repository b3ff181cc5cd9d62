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
pub(crate) const MAX_NONSYMMETRIC_ORDER: u32 = 4;

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
    /// The preprocessor name its shaders are compiled with, where the method is a
    /// variant of another's fragment shader.
    pub define: Option<&'static str>,
    /// Whether the define changes what the vertex shader passes (more coefficients per
    /// glyph), so that the method has its own vertex shader, compiled with it too.
    pub own_vertex: bool,
}

/// The ray-casting methods, in the order reports list them.
pub(crate) const RAY_CAST_METHODS: [RayCastMethod; 4] = [
    RayCastMethod {
        name: "fixed",
        fragment: "raycast_fixed.frag",
        compute: None,
        uses_ranges: false,
        marches: true,
        define: None,
        own_vertex: false,
    },
    RayCastMethod {
        name: "interval",
        fragment: "raycast_interval.frag",
        compute: None,
        uses_ranges: true,
        marches: false,
        define: None,
        own_vertex: false,
    },
    RayCastMethod {
        name: "affine",
        fragment: "raycast_affine.frag",
        compute: None,
        uses_ranges: true,
        marches: false,
        define: None,
        own_vertex: false,
    },
    RayCastMethod {
        name: "exact",
        fragment: "raycast_exact.frag",
        compute: Some("raycast_exact.comp"),
        uses_ranges: false,
        marches: false,
        define: None,
        own_vertex: false,
    },
];

/// Which tensor layouts a glyph shape's shader is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeLayouts {
    /// The symmetric layout of this order only.
    Symmetric(u32),
    /// Every layout of an even order ([`reciprocal_order`]).
    EvenOrders,
}

/// A glyph shape drawn by a shader of its own, not by the `--method`'s: its name (the
/// `ShapeShader` variant's, in lower case), its shader (the fragment shader, the define
/// it is compiled with, whether its vertex shader is its own) and the layouts it is
/// compiled for. The scene format's `shape` values name these shapes (`plane-min` and
/// `plane-max` share the plane's shader, which draws the root the glyph set asks for).
/// Adding a shape starts here: `build.rs` compiles what this table lists, and the
/// renderer draws the shape's glyph sets with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlyphShapeEntry {
    /// The shape's shader name.
    pub name: &'static str,
    /// Its fragment shader and how it is compiled (`name` is the shape's).
    pub shader: RayCastMethod,
    /// The layouts it is compiled for.
    pub layouts: ShapeLayouts,
    /// Whether any `--method` but the impostor draws it (the ellipsoid's closed form);
    /// otherwise the exact method alone does, and the others refuse it.
    pub every_method: bool,
}

impl GlyphShapeEntry {
    /// Whether the shader is compiled for the layout of `order`, symmetric or not.
    pub const fn compiled_for(&self, symmetric: bool, order: u32) -> bool {
        match self.layouts {
            ShapeLayouts::Symmetric(o) => symmetric && order == o,
            ShapeLayouts::EvenOrders => reciprocal_order(order),
        }
    }
}

/// The glyph shapes with shaders of their own, in the order of `ShapeShader`'s variants
/// after the polynomial glyph.
pub(crate) const GLYPH_SHAPES: [GlyphShapeEntry; 4] = [
    // The closed-form ray/quadric intersection of the diffusion-tensor ellipsoid
    // (`--glyph ellipsoid`, `src/glyph/ellipsoid.rs`): the shader every ellipsoid glyph
    // set is drawn with, whatever the method (but the impostor).
    GlyphShapeEntry {
        name: "ellipsoid",
        shader: RayCastMethod {
            name: "ellipsoid",
            fragment: "raycast_ellipsoid.frag",
            compute: None,
            uses_ranges: false,
            marches: false,
            define: None,
            own_vertex: false,
        },
        layouts: ShapeLayouts::Symmetric(ELLIPSOID_ORDER),
        every_method: true,
    },
    // The exact method on reciprocal glyphs, r(u) = 1/|f(u)| (scene `shape`
    // `reciprocal`): `raycast_exact.frag` compiled with `GLYPHCAST_RECIPROCAL`, whose F
    // is (q . q)^(n-1) - f(q)^2. Even orders only: a form of odd order changes sign on
    // the sphere, where 1/|f| is unbounded.
    GlyphShapeEntry {
        name: "reciprocal",
        shader: RayCastMethod {
            name: "reciprocal",
            fragment: "raycast_exact.frag",
            compute: None,
            uses_ranges: false,
            marches: false,
            define: Some("GLYPHCAST_RECIPROCAL"),
            own_vertex: false,
        },
        layouts: ShapeLayouts::EvenOrders,
        every_method: false,
    },
    // The exact method on plane glyphs, r(u) = 1/λ with λ a root of
    // λ² − T(u) λ + D(u) = 0 (scene `shape` `plane-min` and `plane-max`):
    // `raycast_exact.frag` compiled with `GLYPHCAST_PLANE`, whose F is
    // T(q)² |q|² − (|q|⁴ + D(q))², of degree 12, and whose filter keeps the roots of the
    // set's branch. For the layout of D only; its vertex shader passes T's coefficients
    // too.
    GlyphShapeEntry {
        name: "plane",
        shader: RayCastMethod {
            name: "plane",
            fragment: "raycast_exact.frag",
            compute: None,
            uses_ranges: false,
            marches: false,
            define: Some("GLYPHCAST_PLANE"),
            own_vertex: true,
        },
        layouts: ShapeLayouts::Symmetric(PLANE_ORDER),
        every_method: false,
    },
    // The exact method on ratio glyphs, r(u) = |λ/Q(u)| with λ a root of
    // λ² − T(u) λ + D(u) = 0 (scene `shape` `ratio-min` and `ratio-max`):
    // `raycast_exact.frag` compiled with `GLYPHCAST_RATIO`, whose F is
    // Q(q)² T(q)² − |q|² (Q(q)² + D(q))², of degree 18, and whose filter keeps the roots
    // of the set's branch. For the layout of D only; its vertex shader passes T's and
    // Q's coefficients too.
    GlyphShapeEntry {
        name: "ratio",
        shader: RayCastMethod {
            name: "ratio",
            fragment: "raycast_exact.frag",
            compute: None,
            uses_ranges: false,
            marches: false,
            define: Some("GLYPHCAST_RATIO"),
            own_vertex: true,
        },
        layouts: ShapeLayouts::Symmetric(PLANE_ORDER),
        every_method: false,
    },
];

/// The order of the symmetric tensors that have an ellipsoid (DTI).
pub const ELLIPSOID_ORDER: u32 = 2;

/// The order of a plane or ratio glyph's D (its T and Q have order 4), symmetric.
pub const PLANE_ORDER: u32 = 6;

/// Whether tensors of `order` can have a bounded reciprocal glyph (even orders).
pub const fn reciprocal_order(order: u32) -> bool {
    order >= 2 && order.is_multiple_of(2)
}

/// The highest tensor order of a layout: [`MAX_SYMMETRIC_ORDER`] or
/// `MAX_NONSYMMETRIC_ORDER`.
pub const fn max_order(symmetric: bool) -> u32 {
    if symmetric {
        MAX_SYMMETRIC_ORDER
    } else {
        MAX_NONSYMMETRIC_ORDER
    }
}

/// The integer codes the Rust side writes into the frame's and the glyph sets' uniform
/// blocks and the shaders compare against. `build.rs` serves [`SHADER_CODES`] to every
/// shader as `#include "codes.glsl"` (one `#define NAME VALUE` each), so that both sides
/// read these numbers from here.
pub mod codes {
    /// `FrameParams.modes.x`: no refinement of a bracketed root.
    pub const REFINE_NONE: i32 = 0;
    /// `FrameParams.modes.x`: bisection, `modes.y` steps.
    pub const REFINE_BISECT: i32 = 1;
    /// `FrameParams.modes.x`: one linear interpolation.
    pub const REFINE_INTERP: i32 = 2;
    /// `FrameParams.modes.x`: regula falsi (Illinois), `modes.y` steps.
    pub const REFINE_SECANT: i32 = 3;
    /// `FrameParams.modes.z`: colour by the direction from the glyph centre.
    pub const COLOR_DIRECTION: i32 = 0;
    /// `FrameParams.modes.z`: colour by the radius through a colour map.
    pub const COLOR_MAGNITUDE: i32 = 1;
    /// `FrameParams.modes.z`: one colour.
    pub const COLOR_UNIFORM: i32 = 2;
    /// `FrameParams.modes.z`: two colours by the sign of f at the hit.
    pub const COLOR_SIGN: i32 = 3;
    /// A glyph set's `hide_negative`: negative lobes drawn as |f| (scene `negative: abs`).
    pub const NEGATIVE_ABS: u32 = 0;
    /// A glyph set's `hide_negative`: negative lobes hidden (scene `negative: hide`).
    pub const NEGATIVE_HIDE: u32 = 1;
    /// A plane glyph set's `hide_negative` word (it has no negative lobes): draw the
    /// larger root λ, the smaller radius 1/λ (scene `shape` `plane-min`).
    pub const PLANE_MIN: u32 = 0;
    /// A plane glyph set's `hide_negative` word: the smaller root (`plane-max`).
    pub const PLANE_MAX: u32 = 1;
    /// A ratio glyph set's `hide_negative` word: draw the smaller root λ, the smaller
    /// ratio λ/Q (scene `shape` `ratio-min`).
    pub const RATIO_MIN: u32 = 0;
    /// A ratio glyph set's `hide_negative` word: the larger root (`ratio-max`).
    pub const RATIO_MAX: u32 = 1;
    /// The ray-casting pass's visibility word (the header of its known depths,
    /// `render::visibility`): the second stage of a later pass, which shades the hit
    /// that the first stage found nearest, where it is nearer than the known depth.
    pub const VISIBILITY_SHADE_NEAREST: u32 = 1;
    /// The visibility word: the fragments count their work (`WORK_*`).
    pub const VISIBILITY_COUNT: u32 = 2;
    /// The visibility word: the first stage of a later pass, whose hits open the second
    /// stage's gate (the depth its boxes are tested against) where they are nearer than
    /// the known depth.
    pub const VISIBILITY_GATE: u32 = 4;
    /// The visibility word: one pass front to back in which each hit raises the known
    /// depth of its pixel (atomically), and a fragment whose box lies behind it skips
    /// the root isolation (`Culling::EarlyOut`).
    pub const VISIBILITY_EARLY_OUT: u32 = 8;
    /// Work counter: fragment shader invocations of the glyphs' boxes.
    pub const WORK_FRAGMENTS: u32 = 0;
    /// Work counter: rays whose glyph was evaluated (the exact method: root isolations;
    /// the others: rays marched).
    pub const WORK_EVALUATIONS: u32 = 1;
}

/// Every entry of [`codes`] with its GLSL name, for `build.rs`'s `codes.glsl`.
pub const SHADER_CODES: [(&str, i64); 20] = [
    ("REFINE_NONE", codes::REFINE_NONE as i64),
    ("REFINE_BISECT", codes::REFINE_BISECT as i64),
    ("REFINE_INTERP", codes::REFINE_INTERP as i64),
    ("REFINE_SECANT", codes::REFINE_SECANT as i64),
    ("COLOR_DIRECTION", codes::COLOR_DIRECTION as i64),
    ("COLOR_MAGNITUDE", codes::COLOR_MAGNITUDE as i64),
    ("COLOR_UNIFORM", codes::COLOR_UNIFORM as i64),
    ("COLOR_SIGN", codes::COLOR_SIGN as i64),
    ("NEGATIVE_ABS", codes::NEGATIVE_ABS as i64),
    ("NEGATIVE_HIDE", codes::NEGATIVE_HIDE as i64),
    ("PLANE_MIN", codes::PLANE_MIN as i64),
    ("PLANE_MAX", codes::PLANE_MAX as i64),
    ("RATIO_MIN", codes::RATIO_MIN as i64),
    ("RATIO_MAX", codes::RATIO_MAX as i64),
    (
        "VISIBILITY_SHADE_NEAREST",
        codes::VISIBILITY_SHADE_NEAREST as i64,
    ),
    ("VISIBILITY_COUNT", codes::VISIBILITY_COUNT as i64),
    ("VISIBILITY_GATE", codes::VISIBILITY_GATE as i64),
    ("VISIBILITY_EARLY_OUT", codes::VISIBILITY_EARLY_OUT as i64),
    ("WORK_FRAGMENTS", codes::WORK_FRAGMENTS as i64),
    ("WORK_EVALUATIONS", codes::WORK_EVALUATIONS as i64),
];

/// The text of `codes.glsl`: `#define NAME VALUE` for every entry of [`SHADER_CODES`]
/// (int literals; GLSL 4.5 converts them where a uint is compared).
pub fn codes_glsl() -> String {
    let mut text = String::from("// Generated from src/catalog.rs (codes). Do not edit.\n");
    for (name, value) in SHADER_CODES {
        text.push_str(&format!("#define {name} {value}\n"));
    }
    text
}
