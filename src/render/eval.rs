//! Runs a variant's generated glyph function on the GPU at given points (compute shader
//! glsl/glyph_eval.comp), so the generated GLSL can be held against the float64 reference.
use crate::error::{Error, Result, VkContext};
use crate::glyph::TensorLayout;
use crate::render::raycast::shader_module;
use crate::render::shaders::eval_shader;
use crate::vk::{Buffer, DeviceContext, Gpu, OneShot};
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
    let shader = eval_shader(layout)
        .ok_or_else(|| Error::Invalid(format!("no evaluation shader for {layout:?}")))?;
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
    let objects = ComputeObjects::new(
        gpu.context(),
        spirv,
        buffers.len() as u32,
        push.len() as u32,
    )?;
    let infos: Vec<_> = buffers
        .iter()
        .map(|b| {
            [vk::DescriptorBufferInfo {
                buffer: b.handle,
                offset: 0,
                range: vk::WHOLE_SIZE,
            }]
        })
        .collect();
    let writes: Vec<_> = infos
        .iter()
        .enumerate()
        .map(|(i, info)| {
            vk::WriteDescriptorSet::default()
                .dst_set(objects.set)
                .dst_binding(i as u32)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(info)
        })
        .collect();
    // SAFETY: the set and buffers are alive and unused by any command buffer.
    unsafe { device.update_descriptor_sets(&writes, &[]) };
    let commands = OneShot::new(gpu)?;
    commands.run(gpu, |cmd| {
        let host_read = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        // SAFETY: `cmd` is recording; objects live until the submission completes.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, objects.pipeline);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                objects.layout,
                0,
                &[objects.set],
                &[],
            );
            device.cmd_push_constants(cmd, objects.layout, vk::ShaderStageFlags::COMPUTE, 0, push);
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

/// Layouts, pipeline and descriptor set of the evaluation shader; destroyed on drop.
struct ComputeObjects {
    ctx: DeviceContext,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
}

impl ComputeObjects {
    fn new(
        ctx: &DeviceContext,
        spirv: &[u32],
        binding_count: u32,
        push_bytes: u32,
    ) -> Result<ComputeObjects> {
        let device = ctx.device();
        let mut o = ComputeObjects {
            ctx: ctx.clone(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
        };
        let bindings: Vec<_> = (0..binding_count)
            .map(|i| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        // SAFETY: valid infos; every object is destroyed in Drop, also on early return.
        unsafe {
            o.set_layout = device
                .create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                    None,
                )
                .vk("vkCreateDescriptorSetLayout")?;
            let push = [vk::PushConstantRange::default()
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
                .size(push_bytes)];
            let set_layouts = [o.set_layout];
            o.layout = device
                .create_pipeline_layout(
                    &vk::PipelineLayoutCreateInfo::default()
                        .set_layouts(&set_layouts)
                        .push_constant_ranges(&push),
                    None,
                )
                .vk("vkCreatePipelineLayout")?;
            let module = shader_module(device, spirv)?;
            let stage = vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::COMPUTE)
                .module(module)
                .name(c"main");
            let info = vk::ComputePipelineCreateInfo::default()
                .stage(stage)
                .layout(o.layout);
            let created = device.create_compute_pipelines(vk::PipelineCache::null(), &[info], None);
            device.destroy_shader_module(module, None);
            o.pipeline = created
                .map_err(|(_, result)| Error::Vulkan {
                    call: "vkCreateComputePipelines",
                    result,
                })?
                .first()
                .copied()
                .unwrap_or_default();
            let sizes = [vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: binding_count,
            }];
            o.pool = device
                .create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(1)
                        .pool_sizes(&sizes),
                    None,
                )
                .vk("vkCreateDescriptorPool")?;
            o.set = device
                .allocate_descriptor_sets(
                    &vk::DescriptorSetAllocateInfo::default()
                        .descriptor_pool(o.pool)
                        .set_layouts(&set_layouts),
                )
                .vk("vkAllocateDescriptorSets")?[0];
        }
        Ok(o)
    }
}

impl Drop for ComputeObjects {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the one-shot submission has completed; destroying null handles is a
        // no-op; the device is alive while `self.ctx` is.
        unsafe {
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
