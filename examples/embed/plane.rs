//! The engine's own geometry: a square ground plane with its own pipeline and shaders
//! (examples/shaders/plane.vert/.frag, compiled here with shaderc when the pass is made:
//! an engine's shaders are its own, not glyphcast's).
//! It is drawn with an ordinary depth test and depth writes into the depth buffer the
//! glyphs use afterwards.
use super::Result;
use ash::vk;
use bytemuck::{Pod, Zeroable};

/// A square in the plane z = `height`, centred at `center` (x, y) with half-size `half`.
#[derive(Clone, Copy, Debug)]
pub struct Square {
    pub center: [f64; 2],
    pub height: f64,
    pub half: f64,
}

impl Square {
    /// Exact distance along the ray to the square, None for a miss (the analytic plane).
    #[cfg(test)]
    pub fn hit(&self, origin: glam::DVec3, dir: glam::DVec3) -> Option<f64> {
        let t = (self.height - origin.z) / dir.z;
        let p = origin + t * dir;
        let inside =
            (p.x - self.center[0]).abs() <= self.half && (p.y - self.center[1]).abs() <= self.half;
        (t > 0.0 && t.is_finite() && inside).then_some(t)
    }
}

/// The push constants of plane.vert.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PlanePush {
    view_proj: [[f32; 4]; 4],
    square: [f32; 4],
}

/// Borrows the engine's device: the borrow checker keeps the pass from outliving it.
pub struct PlanePass<'a> {
    device: &'a ash::Device,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
}

/// A shader module of one of examples/shaders/plane.*, compiled from GLSL.
fn module(
    device: &ash::Device,
    (name, source): (&str, &str),
    kind: shaderc::ShaderKind,
) -> Result<vk::ShaderModule> {
    let compiler = shaderc::Compiler::new()?;
    let spirv = compiler.compile_into_spirv(source, kind, name, "main", None)?;
    let info = vk::ShaderModuleCreateInfo::default().code(spirv.as_binary());
    // SAFETY: the SPIR-V was produced and checked by glslang just above.
    Ok(unsafe { device.create_shader_module(&info, None)? })
}

const PLANE_VERTEX: (&str, &str) = ("plane.vert", include_str!("../shaders/plane.vert"));
const PLANE_FRAGMENT: (&str, &str) = ("plane.frag", include_str!("../shaders/plane.frag"));

impl<'a> PlanePass<'a> {
    /// A pipeline for the engine's attachments: `samples` per pixel, depth tested with
    /// `compare` (the engine's convention, which glyphcast is told too).
    pub fn new(
        device: &'a ash::Device,
        (color, depth): (vk::Format, vk::Format),
        samples: vk::SampleCountFlags,
        compare: vk::CompareOp,
    ) -> Result<Self> {
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX)
            .size(std::mem::size_of::<PlanePush>() as u32)];
        let layout_info = vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push);
        // SAFETY: valid device; destroyed in Drop.
        let layout = unsafe { device.create_pipeline_layout(&layout_info, None)? };
        let vertex = module(device, PLANE_VERTEX, shaderc::ShaderKind::Vertex)?;
        let fragment = module(device, PLANE_FRAGMENT, shaderc::ShaderKind::Fragment)?;
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vertex)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(fragment)
                .name(c"main"),
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(samples);
        let depth_state = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(compare);
        let blend_attachment = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachment);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let formats = [color];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(depth)
            .stencil_attachment_format(if depth == vk::Format::D32_SFLOAT_S8_UINT {
                depth
            } else {
                vk::Format::UNDEFINED
            });
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth_state)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .push_next(&mut rendering);
        // SAFETY: all state lives until the call returns; the modules may go afterwards.
        let pipeline = unsafe {
            let created =
                device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None);
            device.destroy_shader_module(vertex, None);
            device.destroy_shader_module(fragment, None);
            created.map_err(|(_, e)| e)?[0]
        };
        Ok(PlanePass {
            device,
            layout,
            pipeline,
        })
    }

    /// Draws the square inside the caller's dynamic rendering, with the engine's
    /// view-projection (the one glyphcast is given) so that both write comparable depths.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        rect: vk::Rect2D,
        view_proj: [[f32; 4]; 4],
        square: &Square,
    ) {
        let push = PlanePush {
            view_proj,
            square: [
                square.center[0] as f32,
                square.center[1] as f32,
                square.height as f32,
                square.half as f32,
            ],
        };
        let viewport = vk::Viewport {
            x: rect.offset.x as f32,
            y: rect.offset.y as f32,
            width: rect.extent.width as f32,
            height: rect.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: `cmd` is inside dynamic rendering with formats matching the pipeline.
        unsafe {
            let d = self.device;
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            d.cmd_set_viewport(cmd, 0, &[viewport]);
            d.cmd_set_scissor(cmd, 0, &[rect]);
            d.cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&push),
            );
            d.cmd_draw(cmd, 6, 1, 0, 0);
        }
    }
}

impl Drop for PlanePass<'_> {
    fn drop(&mut self) {
        // SAFETY: the frames recorded with the pipeline have completed.
        unsafe {
            self.device.destroy_pipeline(self.pipeline, None);
            self.device.destroy_pipeline_layout(self.layout, None);
        }
    }
}
