//! Pipeline objects that own themselves: a descriptor-set layout with its pipeline layout,
//! shader modules, pipelines and keyed sets of them, each destroyed when dropped; and the
//! creation of compute and graphics pipelines that the passes share. Passes hold these and
//! need no teardown code of their own; since Vulkan lets a pipeline outlive its layout
//! and its shader modules, the order in which they drop does not matter.
use ash::vk;
use std::collections::HashMap;
use std::hash::Hash;

use super::DeviceContext;
use crate::error::{Error, Result, VkContext};

/// One whole-buffer descriptor at `binding` of type `kind`, seen by `stages`.
pub fn buffer_binding(
    binding: u32,
    kind: vk::DescriptorType,
    stages: vk::ShaderStageFlags,
) -> vk::DescriptorSetLayoutBinding<'static> {
    vk::DescriptorSetLayoutBinding::default()
        .binding(binding)
        .descriptor_type(kind)
        .descriptor_count(1)
        .stage_flags(stages)
}

/// Descriptor-set layouts and the pipeline layout of those sets (and push constants).
pub struct PipelineLayout {
    ctx: DeviceContext,
    set_layouts: Vec<vk::DescriptorSetLayout>,
    layout: vk::PipelineLayout,
}

impl PipelineLayout {
    /// The set of `bindings`, and `push_bytes` bytes of push constants at offset 0 seen by
    /// `push_stages` (none when `push_bytes` is 0).
    pub fn new(
        ctx: &DeviceContext,
        bindings: &[vk::DescriptorSetLayoutBinding],
        push_stages: vk::ShaderStageFlags,
        push_bytes: u32,
    ) -> Result<PipelineLayout> {
        PipelineLayout::with_sets(ctx, &[bindings], push_stages, push_bytes)
    }

    /// [`PipelineLayout::new`] of several sets: set k has the bindings `sets[k]`.
    pub fn with_sets(
        ctx: &DeviceContext,
        sets: &[&[vk::DescriptorSetLayoutBinding]],
        push_stages: vk::ShaderStageFlags,
        push_bytes: u32,
    ) -> Result<PipelineLayout> {
        let device = ctx.device();
        let mut this = PipelineLayout {
            ctx: ctx.clone(),
            set_layouts: Vec::with_capacity(sets.len()),
            layout: vk::PipelineLayout::null(),
        };
        for bindings in sets {
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
            // SAFETY: valid create info; the device is alive while `ctx` is; `this`
            // destroys what was made, also when a later call fails (null handles are
            // ignored).
            let set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
                .vk("vkCreateDescriptorSetLayout")?;
            this.set_layouts.push(set_layout);
        }
        let push = [vk::PushConstantRange::default()
            .stage_flags(push_stages)
            .offset(0)
            .size(push_bytes)];
        let mut info = vk::PipelineLayoutCreateInfo::default().set_layouts(&this.set_layouts);
        if push_bytes > 0 {
            info = info.push_constant_ranges(&push);
        }
        // SAFETY: as above.
        this.layout =
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        Ok(this)
    }

    /// The descriptor-set layout of set 0.
    pub fn set_layout(&self) -> vk::DescriptorSetLayout {
        self.set_layouts[0]
    }

    /// The layout of set `index`, if the pipeline layout has that many sets.
    pub fn set_layout_at(&self, index: usize) -> Option<vk::DescriptorSetLayout> {
        self.set_layouts.get(index).copied()
    }

    /// The pipeline layout.
    pub fn handle(&self) -> vk::PipelineLayout {
        self.layout
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the owner has waited for every frame recorded with the layouts; null
        // handles are ignored; the device is alive while `self.ctx` is.
        unsafe {
            device.destroy_pipeline_layout(self.layout, None);
            for &set_layout in &self.set_layouts {
                device.destroy_descriptor_set_layout(set_layout, None);
            }
        }
    }
}

/// A shader module, destroyed when dropped.
pub struct ShaderModule {
    ctx: DeviceContext,
    handle: vk::ShaderModule,
}

impl ShaderModule {
    /// A module of `spirv`.
    ///
    /// # Safety
    /// `spirv` must be valid SPIR-V for this device (the shaders `build.rs` compiled are).
    pub unsafe fn new(ctx: &DeviceContext, spirv: &[u32]) -> Result<ShaderModule> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: the caller vouches for the SPIR-V; the device is alive while `ctx` is.
        let handle =
            unsafe { ctx.device().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        Ok(ShaderModule {
            ctx: ctx.clone(),
            handle,
        })
    }

    /// A module of the fragment shader `spirv`, rewritten for a device without
    /// `fragmentStoresAndAtomics` (`vk::spirv::without_buffer_writes`) where `ctx` has it
    /// not.
    ///
    /// # Safety
    /// As [`ShaderModule::new`]; a fragment shader whose buffer writes run only where the
    /// device has the feature (the `VISIBILITY` constant of the ray casters).
    pub(crate) unsafe fn fragment(ctx: &DeviceContext, spirv: &[u32]) -> Result<ShaderModule> {
        if ctx.fragment_stores() {
            // SAFETY: the caller's promise.
            return unsafe { ShaderModule::new(ctx, spirv) };
        }
        let rewritten = super::spirv::without_buffer_writes(spirv).ok_or(Error::Setup {
            missing: "a fragment shader of whole SPIR-V instructions",
            found: None,
        })?;
        // SAFETY: the caller's promise; the rewrite keeps the module valid.
        unsafe { ShaderModule::new(ctx, &rewritten) }
    }

    /// The module's handle.
    pub fn handle(&self) -> vk::ShaderModule {
        self.handle
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: pipelines made from the module do not need it any more; the device is
        // alive while `self.ctx` is.
        unsafe { self.ctx.device().destroy_shader_module(self.handle, None) };
    }
}

/// A pipeline, destroyed when dropped.
pub struct Pipeline {
    ctx: DeviceContext,
    handle: vk::Pipeline,
}

impl Pipeline {
    /// Takes ownership of `handle`.
    ///
    /// # Safety
    /// `handle` must be a pipeline of `ctx`'s device that nothing else destroys.
    pub unsafe fn from_raw(ctx: &DeviceContext, handle: vk::Pipeline) -> Pipeline {
        Pipeline {
            ctx: ctx.clone(),
            handle,
        }
    }

    /// The pipeline's handle.
    pub fn handle(&self) -> vk::Pipeline {
        self.handle
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // SAFETY: the owner has waited for every frame recorded with the pipeline; the
        // device is alive while `self.ctx` is.
        unsafe { self.ctx.device().destroy_pipeline(self.handle, None) };
    }
}

/// Pipelines by key, each created once and destroyed with the map.
pub struct Pipelines<K> {
    map: HashMap<K, Pipeline>,
}

impl<K: Hash + Eq> Pipelines<K> {
    /// No pipelines yet.
    pub fn new() -> Self {
        Pipelines {
            map: HashMap::new(),
        }
    }

    /// The pipeline of `key`, if it was made.
    pub fn get(&self, key: &K) -> Option<vk::Pipeline> {
        self.map.get(key).map(Pipeline::handle)
    }

    /// Keeps `pipeline` as `key`'s (a pipeline the key had is dropped: only between
    /// frames) and returns its handle.
    pub fn insert(&mut self, key: K, pipeline: Pipeline) -> vk::Pipeline {
        let handle = pipeline.handle();
        self.map.insert(key, pipeline);
        handle
    }

    /// How many pipelines were made.
    pub fn len(&self) -> usize {
        self.map.len()
    }

    /// Whether none was made yet.
    pub fn is_empty(&self) -> bool {
        self.map.is_empty()
    }
}

impl<K: Hash + Eq> Default for Pipelines<K> {
    fn default() -> Self {
        Self::new()
    }
}

/// A compute pipeline of `spirv`'s `main` in `layout`, with optional specialisation.
///
/// # Safety
/// `spirv` must be valid SPIR-V for this device, matching `layout`.
pub unsafe fn compute_pipeline(
    ctx: &DeviceContext,
    layout: vk::PipelineLayout,
    spirv: &[u32],
    specialization: Option<&vk::SpecializationInfo>,
) -> Result<Pipeline> {
    // SAFETY: the caller vouches for the SPIR-V.
    let module = unsafe { ShaderModule::new(ctx, spirv)? };
    let mut stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module.handle())
        .name(c"main");
    if let Some(specialization) = specialization {
        stage = stage.specialization_info(specialization);
    }
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout);
    // SAFETY: all referenced state lives until the call returns.
    let created = unsafe {
        ctx.device()
            .create_compute_pipelines(ctx.pipeline_cache(), &[info], None)
    };
    let handle = first_pipeline(created, "vkCreateComputePipelines")?;
    // SAFETY: just made on `ctx`'s device, owned by nothing else.
    Ok(unsafe { Pipeline::from_raw(ctx, handle) })
}

/// The one pipeline of a `vkCreate*Pipelines` call for one create info.
fn first_pipeline(
    created: std::result::Result<Vec<vk::Pipeline>, (Vec<vk::Pipeline>, vk::Result)>,
    call: &'static str,
) -> Result<vk::Pipeline> {
    created
        .map_err(|(_, result)| Error::Vulkan { call, result })?
        .first()
        .copied()
        .ok_or(Error::Vulkan {
            call,
            result: vk::Result::INCOMPLETE,
        })
}

/// How the target a pipeline draws into is rasterised and depth-tested: what an
/// embedding host decides (its sample count, its depth convention, its pipeline cache).
/// The default is glyphcast's own: one sample, reversed depth tested GREATER, no cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RasterTarget {
    /// Samples per pixel of the attachments.
    pub samples: vk::SampleCountFlags,
    /// Whether the fragment shader runs once per covered sample (minSampleShading 1): a
    /// ray-cast fragment then casts the ray through its sample, so that multisampled
    /// silhouettes and depths are exact per sample. Needs the sampleRateShading feature.
    pub sample_shading: bool,
    /// The depth test (GREATER for reversed depth, LESS for standard).
    pub depth_compare: vk::CompareOp,
    /// A pipeline cache of the host's, or null.
    pub cache: vk::PipelineCache,
    /// A render pass of the host's and the subpass drawn in; null: dynamic rendering with
    /// the attachment formats.
    pub render_pass: vk::RenderPass,
    /// The subpass of `render_pass`.
    pub subpass: u32,
}

impl Default for RasterTarget {
    fn default() -> Self {
        RasterTarget {
            samples: vk::SampleCountFlags::TYPE_1,
            sample_shading: false,
            depth_compare: vk::CompareOp::GREATER,
            cache: vk::PipelineCache::null(),
            render_pass: vk::RenderPass::null(),
            subpass: 0,
        }
    }
}

/// What differs between the graphics pipelines of the passes; everything else is shared:
/// triangle lists, dynamic viewport and scissor, depth tested and written, every colour
/// attachment written whole without blending, and dynamic rendering with the given
/// attachment formats.
pub struct GraphicsPipelineDesc<'a> {
    /// The vertex and fragment stages.
    pub stages: &'a [vk::PipelineShaderStageCreateInfo<'a>],
    /// Vertex buffer bindings (none: the vertex shader makes its own positions).
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    /// Vertex attributes of those bindings.
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    /// Faces culled (front faces are counter-clockwise).
    pub cull: vk::CullModeFlags,
    /// The colour attachments' formats, in attachment order.
    pub color_formats: &'a [vk::Format],
    /// The depth attachment's format.
    pub depth_format: vk::Format,
    /// The pipeline layout.
    pub layout: vk::PipelineLayout,
    /// Samples, depth test and pipeline cache.
    pub raster: RasterTarget,
    /// Whether it draws over what earlier draws left, to darken it, and its depth test
    /// then: depth not written, colour attachment 0 blended to the smaller of what is
    /// there and the output, the other attachments not written. `EQUAL` redraws the
    /// same triangles.
    pub darken: Option<vk::CompareOp>,
    /// Which stage of the glyphs' later passes it draws (render::visibility); depth is
    /// tested but not written in both early stages.
    pub stage: DrawStage,
}

/// The stages of the glyphs' passes after the first (render::visibility).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DrawStage {
    /// Every other draw: depth tested and written, colours written whole.
    Normal,
    /// The nearest hit of the pass: every attachment blended to the smaller value (the
    /// ray distance at attachment 1; attachment 0 is a scratch image).
    Nearest,
    /// The hits that the pixels show: colours written whole, depth not written (the
    /// shader writes it into the known depths).
    Shade,
}

/// The vertex and fragment stages of a graphics pipeline, both entering at `main`; the
/// vertex stage with `specialization`, where there is one.
pub fn vertex_fragment_stages<'a>(
    vertex: vk::ShaderModule,
    fragment: vk::ShaderModule,
    specialization: Option<&'a vk::SpecializationInfo<'a>>,
) -> [vk::PipelineShaderStageCreateInfo<'a>; 2] {
    specialized_stages(vertex, fragment, (specialization, None))
}

/// [`vertex_fragment_stages`] with specialisation constants for each stage.
pub(crate) fn specialized_stages<'a>(
    vertex: vk::ShaderModule,
    fragment: vk::ShaderModule,
    (vertex_constants, fragment_constants): (
        Option<&'a vk::SpecializationInfo<'a>>,
        Option<&'a vk::SpecializationInfo<'a>>,
    ),
) -> [vk::PipelineShaderStageCreateInfo<'a>; 2] {
    let mut vertex_stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::VERTEX)
        .module(vertex)
        .name(c"main");
    if let Some(specialization) = vertex_constants {
        vertex_stage = vertex_stage.specialization_info(specialization);
    }
    let mut fragment_stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::FRAGMENT)
        .module(fragment)
        .name(c"main");
    if let Some(specialization) = fragment_constants {
        fragment_stage = fragment_stage.specialization_info(specialization);
    }
    [vertex_stage, fragment_stage]
}

/// A graphics pipeline for dynamic rendering, as `desc` describes.
///
/// # Safety
/// The stages' modules must be live and their SPIR-V valid for this device and `layout`.
pub unsafe fn graphics_pipeline(
    ctx: &DeviceContext,
    desc: &GraphicsPipelineDesc,
) -> Result<Pipeline> {
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(desc.vertex_bindings)
        .vertex_attribute_descriptions(desc.vertex_attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(desc.cull)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let mut multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(desc.raster.samples);
    if desc.raster.sample_shading {
        multisample = multisample
            .sample_shading_enable(true)
            .min_sample_shading(1.0);
    }
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(desc.darken.is_none() && desc.stage == DrawStage::Normal)
        .depth_compare_op(desc.darken.unwrap_or(desc.raster.depth_compare));
    let blend_attachments: Vec<_> = (0..desc.color_formats.len())
        .map(|k| {
            let opaque = vk::PipelineColorBlendAttachmentState::default()
                .color_write_mask(vk::ColorComponentFlags::RGBA);
            // MIN ignores the blend factors.
            let min = |state: vk::PipelineColorBlendAttachmentState| {
                state
                    .blend_enable(true)
                    .color_blend_op(vk::BlendOp::MIN)
                    .alpha_blend_op(vk::BlendOp::MIN)
                    .src_color_blend_factor(vk::BlendFactor::ONE)
                    .dst_color_blend_factor(vk::BlendFactor::ONE)
                    .src_alpha_blend_factor(vk::BlendFactor::ONE)
                    .dst_alpha_blend_factor(vk::BlendFactor::ONE)
            };
            // Every attachment alike (a device without independentBlend takes no other):
            // the stage's colour output goes to a scratch image.
            if desc.stage == DrawStage::Nearest {
                return min(opaque);
            }
            match (desc.darken.is_some(), k) {
                (false, _) => opaque,
                (true, 0) => min(opaque),
                (true, _) => opaque.color_write_mask(vk::ColorComponentFlags::empty()),
            }
        })
        .collect();
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    // A depth-stencil format (D24S8, D32S8: most engines' depth buffer) is bound as the
    // rendering's stencil attachment too, so the pipeline names it there; the glyphs
    // leave the stencil untouched (its test stays off).
    let stencil_format = if has_stencil(desc.depth_format) {
        desc.depth_format
    } else {
        vk::Format::UNDEFINED
    };
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(desc.color_formats)
        .depth_attachment_format(desc.depth_format)
        .stencil_attachment_format(stencil_format);
    let mut info = vk::GraphicsPipelineCreateInfo::default()
        .stages(desc.stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(desc.layout);
    info = if desc.raster.render_pass == vk::RenderPass::null() {
        info.push_next(&mut rendering)
    } else {
        info.render_pass(desc.raster.render_pass)
            .subpass(desc.raster.subpass)
    };
    // SAFETY: all referenced state lives until the call returns; the caller vouches for
    // the stages.
    // The host's cache if it gave one, else glyphcast's own (on disk) for its devices.
    let cache = if desc.raster.cache == vk::PipelineCache::null() {
        ctx.pipeline_cache()
    } else {
        desc.raster.cache
    };
    let created = unsafe { ctx.device().create_graphics_pipelines(cache, &[info], None) };
    let handle = first_pipeline(created, "vkCreateGraphicsPipelines")?;
    // SAFETY: just made on `ctx`'s device, owned by nothing else.
    Ok(unsafe { Pipeline::from_raw(ctx, handle) })
}

/// Whether a depth attachment format has a stencil component.
pub(crate) fn has_stencil(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::D16_UNORM_S8_UINT
            | vk::Format::D24_UNORM_S8_UINT
            | vk::Format::D32_SFLOAT_S8_UINT
            | vk::Format::S8_UINT
    )
}
