//! Runs a variant's generated glyph function on the GPU at given points (compute shader
//! glsl/glyph_eval.comp), so the generated GLSL can be held against the float64 reference.
use crate::error::{Error, Result};
use crate::glyph::TensorLayout;
use crate::render::shaders::eval_shader;
use crate::vk::{
    Buffer, BufferBinding, DescriptorPool, Gpu, OneShot, PipelineLayout, buffer_binding,
    compute_pipeline,
};
use ash::vk;
use gpu_allocator::MemoryLocation;

/// f and gradient at each point: `coefficients` holds one or more glyphs' tensors
/// (`layout.coefficient_count()` each); `points` are (x, y, z, glyph index).
/// Returns (f, df/dx, df/dy, df/dz) per point.
pub fn evaluate_on_gpu(
    gpu: &Gpu,
    layout: TensorLayout,
    coefficients: &[f32],
    points: &[[f32; 4]],
) -> Result<Vec<[f32; 4]>> {
    let shader = eval_shader(layout).ok_or_else(|| Error::Unsupported {
        what: crate::error::Asked::Layout(layout.into()),
        by: "the evaluation shaders".into(),
    })?;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let coeff_buffer =
        Buffer::with_data(gpu.context(), "eval coefficients", coefficients, storage)?;
    let point_buffer = Buffer::with_data(gpu.context(), "eval points", points, storage)?;
    let result_buffer = Buffer::new(
        gpu.context(),
        "eval results",
        16 * points.len() as u64,
        storage,
        MemoryLocation::GpuToCpu,
    )?;
    let count = points.len() as u32;
    dispatch(
        gpu,
        shader.spirv,
        &[&coeff_buffer, &point_buffer, &result_buffer],
        &count.to_ne_bytes(),
        count,
    )?;
    Ok(bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(
        result_buffer.read()?,
    ))
}

/// Runs a compute shader of local size 64 over `count` invocations, with `buffers` bound
/// as storage buffers 0, 1, ... and `push` as its push constants; waits for it and checks
/// the validation layer.
pub(crate) fn dispatch(
    gpu: &Gpu,
    spirv: &[u32],
    buffers: &[&Buffer],
    push: &[u8],
    count: u32,
) -> Result<()> {
    let device = gpu.device();
    let ctx = gpu.context();
    let bindings: Vec<_> = (0..buffers.len() as u32)
        .map(|i| {
            buffer_binding(
                i,
                vk::DescriptorType::STORAGE_BUFFER,
                vk::ShaderStageFlags::COMPUTE,
            )
        })
        .collect();
    let layout = PipelineLayout::new(
        ctx,
        &bindings,
        vk::ShaderStageFlags::COMPUTE,
        push.len() as u32,
    )?;
    // SAFETY: the caller's SPIR-V comes from build.rs and declares these bindings.
    let pipeline = unsafe { compute_pipeline(ctx, layout.handle(), spirv, None)? };
    let handle = pipeline.handle();
    let pool = DescriptorPool::new(ctx, 1, 0, buffers.len() as u32)?;
    let storage: Vec<_> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| BufferBinding::storage(i as u32, b))
        .collect();
    let set = pool.buffer_set(layout.set_layout(), &storage)?;
    let commands = OneShot::new(gpu)?;
    commands.run(gpu, |cmd| {
        let host_read = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        // SAFETY: `cmd` is recording; objects live until the submission completes.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, handle);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                layout.handle(),
                0,
                &[set],
                &[],
            );
            device.cmd_push_constants(cmd, layout.handle(), vk::ShaderStageFlags::COMPUTE, 0, push);
            device.cmd_dispatch(cmd, count.div_ceil(64), 1, 1);
            device.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&host_read),
            );
        }
        Ok(())
    })?;
    gpu.check_validation()
}
