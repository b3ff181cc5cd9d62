//! The SPIR-V that build.rs generated for the orders and methods of `crate::catalog`, as
//! a typed table.
use crate::glyph::{Symmetry, TensorLayout};
use crate::render::{Method, ShapeShader};

/// Compute shader that evaluates f and its gradient at given points (for tests).
pub struct EvalShader {
    /// The tensor layout it is generated for.
    pub layout: TensorLayout,
    /// Its SPIR-V (glsl/glyph_eval.comp).
    pub spirv: &'static [u32],
}

/// Compute shader that evaluates the interval and affine ranges of f and G over ray
/// segments (for tests of the robust methods).
pub struct RangeShader {
    /// The tensor layout it is generated for.
    pub layout: TensorLayout,
    /// Its SPIR-V (glsl/glyph_range.comp).
    pub spirv: &'static [u32],
}

/// Ray-casting fragment shader of one tensor layout and intersection method.
pub struct RaycastShader {
    /// The tensor layout it is generated for.
    pub layout: TensorLayout,
    /// The intersection method of its fragment shaders (a glyph shape's own shader is
    /// the exact method's).
    pub method: Method,
    /// The glyph shape it draws: the polynomial glyph, or a shape with a shader of its
    /// own.
    pub shape: ShapeShader,
    /// The proxy boxes' vertex shader of this layout, which passes the glyph's monomial
    /// coefficients to the fragment shader as flat inputs (locations 4 and up).
    pub vertex: &'static [u32],
    /// Writes colour (location 0) and the ray distance (location 1).
    pub fragment: &'static [u32],
    /// The same shader compiled without the distance output, for renderings with a
    /// colour attachment only: a fragment output with no attachment to receive it is
    /// reported by the validation layer (and wastes the write).
    pub color_only_fragment: &'static [u32],
    /// The exact method's fragment shader that casts shadow rays (`--shadows`): the
    /// `fragment` shader's outputs, lit by the share of the light that reaches the hit.
    pub shadows_fragment: Option<&'static [u32]>,
    /// The same without the distance output, for colour-only targets.
    pub shadows_color_only_fragment: Option<&'static [u32]>,
    /// The exact method's underlay receiver: the underlay's planes drawn again after the
    /// batch (with `UNDERLAY_RECEIVER_VERTEX`), darkened by the batch's shadows and
    /// occlusion (`src/render/underlay_shadows.rs`).
    pub receiver_fragment: Option<&'static [u32]>,
    /// The exact method's glyph receiver: the batch's boxes drawn again after a frame
    /// drawn without shadows, shading the hits the frame's distance attachment holds
    /// with the share of the light and occlusion that reaches them
    /// (`src/render/glyph_shadows.rs`).
    pub glyph_receiver_fragment: Option<&'static [u32]>,
}

/// Compute ray caster of one tensor layout and intersection method (`--path compute`,
/// `glsl/raycast_<method>.comp`): one invocation per pixel walks its screen tile's glyphs.
pub struct ComputeRaycastShader {
    /// The tensor layout it is generated for.
    pub layout: TensorLayout,
    /// Its intersection method.
    pub method: Method,
    /// Its SPIR-V.
    pub spirv: &'static [u32],
}

/// SPIR-V bytes with the alignment of words, so they can be read as `&[u32]`.
#[repr(C)]
struct WordAligned<const N: usize> {
    _words: [u32; 0],
    bytes: [u8; N],
}

/// A SPIR-V file of `$OUT_DIR` (build.rs writes whole little-endian words, and fails the
/// build for big-endian targets) as a static slice of words.
macro_rules! spirv {
    ($file:literal) => {{
        const BYTES: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), $file));
        static ALIGNED: WordAligned<{ BYTES.len() }> = WordAligned {
            _words: [],
            bytes: *include_bytes!(concat!(env!("OUT_DIR"), $file)),
        };
        // SAFETY: the bytes are aligned for u32 (the zero-length [u32; 0] field), live
        // for the whole program, and are BYTES.len() / 4 whole words (build.rs writes
        // only whole words).
        unsafe { std::slice::from_raw_parts(ALIGNED.bytes.as_ptr().cast::<u32>(), BYTES.len() / 4) }
    }};
}

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The ray-casting shaders of `layout`, `method` and `shape`; None if the catalog has
/// none.
pub(crate) fn raycast_shader(
    layout: TensorLayout,
    method: Method,
    shape: ShapeShader,
) -> Option<&'static RaycastShader> {
    RAYCAST_SHADERS
        .iter()
        .find(|s| s.layout == layout && s.method == method && s.shape == shape)
}

/// The compute ray caster of `layout` and `method`; None if the catalog has none.
pub(crate) fn compute_raycast_shader(
    layout: TensorLayout,
    method: Method,
) -> Option<&'static ComputeRaycastShader> {
    COMPUTE_RAYCAST_SHADERS
        .iter()
        .find(|s| s.layout == layout && s.method == method)
}

/// The evaluation shader of `layout`; None if the catalog has none.
pub(crate) fn eval_shader(layout: TensorLayout) -> Option<&'static EvalShader> {
    EVAL_SHADERS.iter().find(|s| s.layout == layout)
}

/// The range shader of `layout`; None if no method of the layout uses ranges.
pub(crate) fn range_shader(layout: TensorLayout) -> Option<&'static RangeShader> {
    RANGE_SHADERS.iter().find(|s| s.layout == layout)
}

/// The intersection methods (`--method`) that have a shader for every layout in
/// `layouts`, sorted; the ellipsoid's shader is not one.
pub fn methods_for(layouts: &[TensorLayout]) -> Vec<Method> {
    let mut methods: Vec<Method> = RAYCAST_SHADERS
        .iter()
        .filter(|s| s.shape == ShapeShader::Polynomial)
        .map(|s| s.method)
        .filter(|m| Method::RAY_CASTING.contains(m))
        .collect();
    methods.sort();
    methods.dedup();
    let polynomial = ShapeShader::Polynomial;
    methods.retain(|m| {
        layouts
            .iter()
            .all(|l| raycast_shader(*l, *m, polynomial).is_some())
    });
    methods
}

/// Every tensor layout that has shaders.
pub fn layouts() -> impl Iterator<Item = TensorLayout> {
    EVAL_SHADERS.iter().map(|s| s.layout)
}

#[allow(dead_code)]
const _: Symmetry = Symmetry::Symmetric;

#[cfg(test)]
mod tests {
    use super::*;

    /// Locations of the fragment outputs a SPIR-V module declares.
    fn output_locations(spirv: &[u32]) -> Vec<u32> {
        const OP_DECORATE: u32 = 71;
        const OP_VARIABLE: u32 = 59;
        const DECORATION_LOCATION: u32 = 30;
        const STORAGE_OUTPUT: u32 = 3;
        let (mut locations, mut outputs) = (Vec::new(), Vec::new());
        let mut at = 5; // past the header
        while at < spirv.len() {
            let (count, opcode) = ((spirv[at] >> 16) as usize, spirv[at] & 0xffff);
            let words = &spirv[at..at + count.max(1)];
            if opcode == OP_DECORATE && words.len() == 4 && words[2] == DECORATION_LOCATION {
                locations.push((words[1], words[3]));
            } else if opcode == OP_VARIABLE && words.len() >= 4 && words[3] == STORAGE_OUTPUT {
                outputs.push(words[2]);
            }
            at += count.max(1);
        }
        let mut found: Vec<u32> = locations
            .iter()
            .filter(|(id, _)| outputs.contains(id))
            .map(|(_, location)| *location)
            .collect();
        found.sort();
        found
    }

    /// Guards new methods' shaders: each must wrap its distance output in
    /// `#ifndef GLYPHCAST_NO_DISTANCE` so that the colour-only variant has none.
    #[test]
    fn colour_only_variants_write_location_0_only() {
        for shader in RAYCAST_SHADERS {
            let what = format!("{:?} {:?}", shader.layout, shader.method);
            assert_eq!(output_locations(shader.fragment), [0, 1], "{what}");
            if let Some(shadows) = shader.shadows_fragment {
                assert_eq!(output_locations(shadows), [0, 1], "{what} with shadows");
            }
            if let Some(shadows) = shader.shadows_color_only_fragment {
                assert_eq!(output_locations(shadows), [0], "{what} with shadows");
            }
            assert_eq!(
                output_locations(shader.color_only_fragment),
                [0],
                "{what}: wrap out_distance in #ifndef GLYPHCAST_NO_DISTANCE"
            );
        }
    }
}

/// The depth convention of a target: which end of the depth range is near, and so which
/// depth test keeps the nearer surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthConvention {
    /// Near at 1, far at 0 (or at infinity): cleared to 0, tested GREATER. glyphcast's own.
    #[default]
    Reversed,
    /// Near at 0, far at 1: cleared to 1, tested LESS.
    Standard,
}

impl DepthConvention {
    /// The window depth of the near plane.
    pub fn near_depth(self) -> f32 {
        match self {
            DepthConvention::Reversed => 1.0,
            DepthConvention::Standard => 0.0,
        }
    }

    /// The window depth a depth buffer is cleared to (the far end).
    pub fn clear_depth(self) -> f32 {
        1.0 - self.near_depth()
    }

    /// The depth test that keeps the nearer surface.
    pub fn compare_op(self) -> ash::vk::CompareOp {
        match self {
            DepthConvention::Reversed => ash::vk::CompareOp::GREATER,
            DepthConvention::Standard => ash::vk::CompareOp::LESS,
        }
    }
}

/// SPIR-V's OpExecutionMode and the conservative-depth modes it may carry.
const OP_EXECUTION_MODE: u32 = 16;
const DEPTH_GREATER: u32 = 14;
const DEPTH_LESS: u32 = 15;

/// A fragment shader's SPIR-V for targets of `depth`. The ray casters declare
/// `layout(depth_less) out float gl_FragDepth` (a hit lies behind the box face the
/// rasteriser produced, which under reversed depth is a smaller depth); under standard
/// depth the same hit is a larger depth, so the promise becomes `depth_greater`. That is
/// the one word the two variants differ in (the DepthLess execution mode becomes
/// DepthGreater), so it is rewritten here rather than compiled twice in build.rs.
pub(crate) fn for_depth(spirv: &[u32], depth: DepthConvention) -> Vec<u32> {
    match depth {
        DepthConvention::Reversed => spirv.to_vec(),
        DepthConvention::Standard => with_execution_mode(spirv, DEPTH_LESS, DEPTH_GREATER),
    }
}

/// `spirv` with the fragment execution mode `from` (a mode of no operands) turned into
/// `to`.
fn with_execution_mode(spirv: &[u32], from: u32, to: u32) -> Vec<u32> {
    let mut words = spirv.to_vec();
    for (at, opcode, count) in crate::vk::spirv::walk(spirv) {
        if opcode == OP_EXECUTION_MODE && count == 3 && words[at + 2] == from {
            words[at + 2] = to;
        }
    }
    words
}

/// SPIR-V's EarlyFragmentTests execution mode.
const EARLY_FRAGMENT_TESTS: u32 = 9;

/// A ray-casting fragment shader's SPIR-V with the depth test before it runs (the
/// EarlyFragmentTests mode in place of the DepthLess promise, one word): the early stages
/// of the glyphs' later passes (render::visibility), whose fragments behind the depth
/// attachment never run. Their pipelines do not write depth.
pub(crate) fn with_early_tests(spirv: &[u32]) -> Vec<u32> {
    with_execution_mode(spirv, DEPTH_LESS, EARLY_FRAGMENT_TESTS)
}

#[cfg(test)]
mod depth_tests {
    use super::*;

    /// Execution modes of a SPIR-V module (mode words of every OpExecutionMode).
    fn execution_modes(spirv: &[u32]) -> Vec<u32> {
        crate::vk::spirv::walk(spirv)
            .filter(|&(_, opcode, _)| opcode == OP_EXECUTION_MODE)
            .map(|(at, _, _)| spirv[at + 2])
            .collect()
    }

    /// Every ray-casting fragment shader promises depth_less, and its standard-depth
    /// variant depth_greater, differing in that word only.
    #[test]
    fn standard_depth_turns_depth_less_into_depth_greater() {
        let shaders = RAYCAST_SHADERS
            .iter()
            .flat_map(|s| {
                [s.fragment, s.color_only_fragment]
                    .into_iter()
                    .chain(s.shadows_fragment)
                    .chain(s.shadows_color_only_fragment)
            })
            .chain([IMPOSTOR_FRAGMENT]);
        for spirv in shaders {
            assert!(execution_modes(spirv).contains(&DEPTH_LESS));
            let standard = for_depth(spirv, DepthConvention::Standard);
            let modes = execution_modes(&standard);
            assert!(modes.contains(&DEPTH_GREATER) && !modes.contains(&DEPTH_LESS));
            let changed = spirv.iter().zip(&standard).filter(|(a, b)| a != b).count();
            assert_eq!(changed, 1);
            assert_eq!(for_depth(spirv, DepthConvention::Reversed), spirv);
        }
    }
}
