//! Runs a variant's generated interval and affine ranges on the GPU over given ray
//! segments (compute shader glsl/glyph_range.comp), so tests can check that they contain
//! the float64 values of f and G they claim to bound.
use crate::error::{Error, Result};
use crate::glyph::TensorLayout;
use crate::render::harness::eval::dispatch;
use crate::render::shaders::range_shader;
use crate::vk::{Buffer, Gpu};
use ash::vk;
use bytemuck::{Pod, Zeroable};
use gpu_allocator::MemoryLocation;

/// One segment q(s) = mid + s dir, s in [s0, s1], in a glyph's normalised frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct RangeQuery {
    /// xyz: mid, w: s0.
    pub mid_s0: [f32; 4],
    /// xyz: dir, w: s1.
    pub dir_s1: [f32; 4],
    /// Index of the glyph in the coefficients.
    pub glyph: u32,
    /// 1 to hide negative lobes (h = max(f, 0)), 0 for h = |f|.
    pub hide_negative: u32,
    /// Isotropic offset w, normalised units.
    pub offset: f32,
    /// Padding to 16-byte alignment; 0.
    pub pad: u32,
}

/// Ranges over one segment, each (f lo, f hi, G lo, G hi), already widened by the
/// shader's rounding allowance.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct RangeResult {
    /// By interval arithmetic.
    pub interval: [f32; 4],
    /// By the reduced affine forms.
    pub affine: [f32; 4],
}

/// The ranges of f and G = h(f) + w |q|^n - |q|^(n+1) over each segment, for glyphs whose
/// tensors (scene format layout) are `coefficients`, `layout.coefficient_count()` each.
pub fn ranges_on_gpu(
    gpu: &Gpu,
    layout: TensorLayout,
    coefficients: &[f32],
    queries: &[RangeQuery],
) -> Result<Vec<RangeResult>> {
    let shader = range_shader(layout).ok_or_else(|| Error::Unsupported {
        what: crate::error::Asked::Layout(layout.into()),
        by: "the range shaders".into(),
    })?;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let coeff_buffer =
        Buffer::with_data(gpu.context(), "range coefficients", coefficients, storage)?;
    let query_buffer = Buffer::with_data(gpu.context(), "range queries", queries, storage)?;
    let result_buffer = Buffer::new(
        gpu.context(),
        "range results",
        (std::mem::size_of::<RangeResult>() * queries.len()) as u64,
        storage,
        MemoryLocation::GpuToCpu,
    )?;
    let count = queries.len() as u32;
    dispatch(
        gpu,
        shader.spirv,
        &[&coeff_buffer, &query_buffer, &result_buffer],
        &count.to_ne_bytes(),
        count,
    )?;
    Ok(bytemuck::pod_collect_to_vec::<u8, RangeResult>(
        result_buffer.read()?,
    ))
}
