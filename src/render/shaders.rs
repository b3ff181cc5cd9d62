//! The SPIR-V that build.rs generated from `glsl/manifest.txt`, as a typed table.
use crate::glyph::{Symmetry, TensorLayout};
use crate::render::Method;

/// Compute shader that evaluates f and its gradient at given points (for tests).
pub struct EvalShader {
    pub layout: TensorLayout,
    pub spirv: &'static [u32],
}

/// Compute shader that evaluates the interval and affine ranges of f and G over ray
/// segments (for tests of the robust methods).
pub struct RangeShader {
    pub layout: TensorLayout,
    pub spirv: &'static [u32],
}

/// Ray-casting fragment shader of one tensor layout and intersection method.
pub struct RaycastShader {
    pub layout: TensorLayout,
    pub method: Method,
    pub fragment: &'static [u32],
}

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

pub fn raycast_shader(layout: TensorLayout, method: Method) -> Option<&'static RaycastShader> {
    RAYCAST_SHADERS
        .iter()
        .find(|s| s.layout == layout && s.method == method)
}

pub fn eval_shader(layout: TensorLayout) -> Option<&'static EvalShader> {
    EVAL_SHADERS.iter().find(|s| s.layout == layout)
}

pub fn range_shader(layout: TensorLayout) -> Option<&'static RangeShader> {
    RANGE_SHADERS.iter().find(|s| s.layout == layout)
}

/// Every tensor layout that has shaders.
pub fn layouts() -> impl Iterator<Item = TensorLayout> {
    EVAL_SHADERS.iter().map(|s| s.layout)
}

#[allow(dead_code)]
const _: Symmetry = Symmetry::Symmetric;
