//! Pipeline objects that own themselves: a descriptor-set layout with its pipeline layout,
//! shader modules and keyed pipelines, each destroyed when dropped. Passes hold these and
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

/// A descriptor-set layout and the pipeline layout of that one set (and push constants).
pub struct PipelineLayout {
    ctx: DeviceContext,
    set_layout: vk::DescriptorSetLayout,
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
        let device = ctx.device();
        let mut this = PipelineLayout {
            ctx: ctx.clone(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
        };
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
        // SAFETY: valid create info; the device is alive while `ctx` is; `this` destroys
        // what was made, also when the second call fails (null handles are ignored).
        this.set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .vk("vkCreateDescriptorSetLayout")?;
        let push = [vk::PushConstantRange::default()
            .stage_flags(push_stages)
            .offset(0)
            .size(push_bytes)];
        let set_layouts = [this.set_layout];
        let mut info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        if push_bytes > 0 {
            info = info.push_constant_ranges(&push);
        }
        // SAFETY: as above.
        this.layout =
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        Ok(this)
    }

    /// The descriptor-set layout (set 0).
    pub fn set_layout(&self) -> vk::DescriptorSetLayout {
        self.set_layout
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
            device.destroy_descriptor_set_layout(self.set_layout, None);
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

/// Pipelines by key, each created once and destroyed with the map.
pub struct Pipelines<K> {
    ctx: DeviceContext,
    map: HashMap<K, vk::Pipeline>,
}

impl<K: Hash + Eq> Pipelines<K> {
    /// No pipelines yet.
    pub fn new(ctx: &DeviceContext) -> Self {
        Pipelines {
            ctx: ctx.clone(),
            map: HashMap::new(),
        }
    }

    /// The pipeline of `key`, if it was made.
    pub fn get(&self, key: &K) -> Option<vk::Pipeline> {
        self.map.get(key).copied()
    }

    /// Takes ownership of `pipeline` as `key`'s (a pipeline the key had is destroyed).
    pub fn insert(&mut self, key: K, pipeline: vk::Pipeline) {
        if let Some(old) = self.map.insert(key, pipeline) {
            // SAFETY: the caller replaces a pipeline only between frames; the device is
            // alive while `self.ctx` is.
            unsafe { self.ctx.device().destroy_pipeline(old, None) };
        }
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

impl<K> Drop for Pipelines<K> {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the owner has waited for every frame recorded with these pipelines; the
        // device is alive while `self.ctx` is.
        unsafe {
            for pipeline in self.map.values() {
                device.destroy_pipeline(*pipeline, None);
            }
        }
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
) -> Result<vk::Pipeline> {
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
            .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
    };
    first_pipeline(created, "vkCreateComputePipelines")
}

/// The one pipeline of a `vkCreate*Pipelines` call for one create info.
pub fn first_pipeline(
    created: std::result::Result<Vec<vk::Pipeline>, (Vec<vk::Pipeline>, vk::Result)>,
    call: &'static str,
) -> Result<vk::Pipeline> {
    created
        .map_err(|(_, result)| Error::Vulkan { call, result })?
        .first()
        .copied()
        .ok_or_else(|| Error::Setup(format!("{call} returned no pipeline")))
}
