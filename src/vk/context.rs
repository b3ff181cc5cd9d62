//! Who destroys the instance and the device, and when.
//!
//! Every buffer, image, command pool and pass keeps a [`DeviceContext`], a clone of one
//! `Arc<DeviceOwner>`; the device goes when the last of them (or the [`Gpu`](super::Gpu))
//! goes, whatever the order in which safe code drops them. The owner of a device that
//! glyphcast created also holds the [`InstanceOwner`], so the teardown is always: the
//! allocator's memory, the device, the debug messenger, the instance. Nothing relies on
//! the declaration order of fields.
//!
//! A device an engine made ([`DeviceContext::new`]) has an owner that destroys nothing:
//! the engine promises to keep its device and allocator until glyphcast's objects are gone.
use super::debug;
use super::memory::{GpuAllocatorMemory, MemoryAllocator};
use super::pipeline_cache::PipelineCacheFile;
use ash::vk;
use gpu_allocator::vulkan::Allocator;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

/// An instance glyphcast created, with its validation messenger. Shared by the
/// [`Gpu`](super::Gpu), the device owner and the window surfaces; the last of them
/// destroys it.
pub(crate) struct InstanceOwner {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub validation: Option<debug::Messenger>,
}

impl Drop for InstanceOwner {
    fn drop(&mut self) {
        // SAFETY: the device and the surfaces hold an Arc of this owner, so they were
        // destroyed before the last Arc went; nothing else was created from the instance.
        unsafe {
            if let Some(m) = &self.validation {
                m.loader.destroy_debug_utils_messenger(m.handle, None);
            }
            // The messenger chained into instance creation still reports into the log,
            // which lives in `self.validation` until after this call.
            self.instance.destroy_instance(None);
        }
        if let Some(m) = &self.validation {
            m.log.report_unread();
        }
    }
}

/// The device, its memory allocator, and what to destroy when the last context goes.
struct DeviceOwner {
    device: ash::Device,
    /// Dropped by hand in `Drop`, before the device. When glyphcast made the device this
    /// is the only handle of the allocator (it is never handed out), so the allocator
    /// frees its memory there; an engine's allocator is the engine's to drop.
    memory: ManuallyDrop<Arc<dyn MemoryAllocator>>,
    /// The instance of a device glyphcast created: the device is destroyed, and the
    /// instance kept alive until then. `None` for an engine's device.
    created: Option<Arc<InstanceOwner>>,
    /// Every pipeline is created through this cache (null: none), which glyphcast made
    /// and destroys, and saves to `cache_file` first.
    pipeline_cache: vk::PipelineCache,
    cache_file: Option<PipelineCacheFile>,
}

impl DeviceOwner {
    /// Saves the pipeline cache to its file (if it has one) and destroys it.
    fn close_pipeline_cache(&mut self) {
        if self.pipeline_cache == vk::PipelineCache::null() {
            return;
        }
        if let Some(file) = &self.cache_file {
            // SAFETY: the cache is alive and no pipeline is being created (the last
            // context is going).
            match unsafe { self.device.get_pipeline_cache_data(self.pipeline_cache) } {
                Ok(data) => file.save(&data),
                Err(e) => eprintln!(
                    "note: {}: the pipeline cache was not saved ({e})",
                    file.path().display()
                ),
            }
        }
        // SAFETY: made on this device by `with_pipeline_cache`; nothing uses it any more.
        unsafe {
            self.device
                .destroy_pipeline_cache(self.pipeline_cache, None)
        };
        self.pipeline_cache = vk::PipelineCache::null();
    }
}

impl Drop for DeviceOwner {
    fn drop(&mut self) {
        if self.created.is_some() {
            // SAFETY: the device is alive; nothing made from it is left (each holds an
            // Arc of this owner), so this only waits for work already submitted.
            let _ = unsafe { self.device.device_wait_idle() };
        }
        self.close_pipeline_cache();
        // SAFETY: the allocator is not used after this, and dropped nowhere else.
        unsafe { ManuallyDrop::drop(&mut self.memory) };
        if self.created.is_some() {
            // SAFETY: every object made from the device held an Arc of this owner and is
            // gone; the allocator freed its memory above; the instance is kept alive by
            // `self.created` until after this body.
            unsafe { self.device.destroy_device(None) };
        }
    }
}

/// What buffers, images and render passes need of a device: the device, an allocator
/// for it, and its limits. Cloning is cheap (an `Arc`), and every object made with a
/// context keeps a clone, so the device outlives them all. [`Gpu`](super::Gpu) makes one
/// for itself; an engine that owns its Vulkan device builds one around its own objects
/// with [`DeviceContext::new`], and glyphcast then creates no instance or device of its
/// own.
#[derive(Clone)]
pub struct DeviceContext {
    owner: Arc<DeviceOwner>,
    max_storage_buffer_range: u64,
    max_varying_components: u32,
    max_image_dimension_2d: u32,
    timestamp_period_ns: f32,
    /// Whether an R32_SFLOAT colour attachment blends (optimal tiling).
    blends_float32: bool,
    /// The physical device's type (a GPU, a CPU such as lavapipe, ...).
    device_type: vk::PhysicalDeviceType,
    /// Whether compute shaders have subgroup vote and ballot operations (the compute ray
    /// caster's walk, glsl/raycast_exact.comp).
    compute_votes: bool,
    /// Whether the device jumps over a branch that no lane of a batch takes (a GPU, and
    /// lavapipe from Mesa 25; Mesa 22.3's runs it masked): culling by early outs.
    skips_idle_branches: bool,
    /// Whether the device was created with `fragmentStoresAndAtomics`: the fragment
    /// shaders' work counters and the culling of hidden glyphs need it. A device
    /// glyphcast creates has it; a host's has it where the host says so
    /// ([`DeviceContext::with_fragment_stores`]).
    fragment_stores: bool,
}

impl DeviceContext {
    /// Wraps a caller's device and gpu-allocator allocator (glyphcast's buffers and
    /// images take their memory from it, through [`GpuAllocatorMemory`]); the limits are
    /// read from `physical_device`. glyphcast destroys none of them.
    ///
    /// # Safety
    /// `device` was created from `physical_device` of `instance` with the features the
    /// passes need (Vulkan 1.3 dynamic rendering), and `allocator` allocates for that
    /// device. The device, the instance and the allocator stay alive until every
    /// glyphcast object made with this context (or a clone of it) has been dropped: the
    /// context, passes, scenes, buffers and images. glyphcast never destroys them, and
    /// its clone of `allocator` must not be the last handle to it when the device goes.
    pub unsafe fn new(
        instance: &ash::Instance,
        physical_device: vk::PhysicalDevice,
        device: ash::Device,
        allocator: Arc<Mutex<Allocator>>,
    ) -> DeviceContext {
        // SAFETY: the caller's promises, the allocator's included.
        unsafe {
            DeviceContext::with_memory(
                instance,
                physical_device,
                device,
                Arc::new(GpuAllocatorMemory::new(allocator)),
            )
        }
    }

    /// [`DeviceContext::new`] with memory from the host's own [`MemoryAllocator`]:
    /// every buffer and image glyphcast makes with this context takes its memory there
    /// and gives it back when dropped.
    ///
    /// # Safety
    /// As [`DeviceContext::new`], with `memory` in place of the allocator: it hands out
    /// memory of `device` as its trait documents, and whatever it allocates from stays
    /// alive until every glyphcast object made with this context has been dropped.
    pub unsafe fn with_memory(
        instance: &ash::Instance,
        physical_device: vk::PhysicalDevice,
        device: ash::Device,
        memory: Arc<dyn MemoryAllocator>,
    ) -> DeviceContext {
        let owner = DeviceOwner {
            device,
            memory: ManuallyDrop::new(memory),
            created: None,
            pipeline_cache: vk::PipelineCache::null(),
            cache_file: None,
        };
        DeviceContext::with_owner(instance, physical_device, owner, false)
    }

    /// The context of a device glyphcast created from `instance`: the last clone
    /// destroys the allocator, the device and (if no one else holds it) the instance.
    pub(crate) fn created(
        instance: Arc<InstanceOwner>,
        physical_device: vk::PhysicalDevice,
        device: ash::Device,
        allocator: Allocator,
    ) -> DeviceContext {
        let handle = instance.instance.clone();
        // SAFETY: the physical device belongs to the instance.
        let props = unsafe { handle.get_physical_device_properties(physical_device) };
        let cache_file = PipelineCacheFile::open(&props);
        let pipeline_cache = create_pipeline_cache(&device, cache_file.as_ref());
        let owner = DeviceOwner {
            device,
            memory: ManuallyDrop::new(Arc::new(GpuAllocatorMemory::new(Arc::new(Mutex::new(
                allocator,
            ))))),
            created: Some(instance),
            pipeline_cache,
            cache_file,
        };
        // device::create enables fragmentStoresAndAtomics.
        DeviceContext::with_owner(&handle, physical_device, owner, true)
    }

    fn with_owner(
        instance: &ash::Instance,
        physical_device: vk::PhysicalDevice,
        owner: DeviceOwner,
        fragment_stores: bool,
    ) -> DeviceContext {
        // SAFETY: the physical device belongs to the instance (the callers' promise).
        let props = unsafe { instance.get_physical_device_properties(physical_device) };
        let limits = props.limits;
        // SAFETY: as above.
        let float32 = unsafe {
            instance.get_physical_device_format_properties(physical_device, vk::Format::R32_SFLOAT)
        };
        let blends_float32 = float32
            .optimal_tiling_features
            .contains(vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND);
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut properties = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut subgroup)
            .push_next(&mut driver);
        // SAFETY: as above; the chain holds structures that Vulkan 1.2 knows (the device
        // has Vulkan 1.3).
        unsafe { instance.get_physical_device_properties2(physical_device, &mut properties) };
        let skips_idle_branches = skips_idle_branches(
            props.device_type,
            driver.driver_id,
            driver.driver_info_as_c_str().ok(),
        );
        let compute_votes = subgroup
            .supported_stages
            .contains(vk::ShaderStageFlags::COMPUTE)
            && subgroup
                .supported_operations
                .contains(vk::SubgroupFeatureFlags::VOTE | vk::SubgroupFeatureFlags::BALLOT);
        DeviceContext {
            blends_float32,
            device_type: props.device_type,
            compute_votes,
            skips_idle_branches,
            fragment_stores,
            owner: Arc::new(owner),
            max_storage_buffer_range: limits.max_storage_buffer_range as u64,
            max_varying_components: limits
                .max_vertex_output_components
                .min(limits.max_fragment_input_components),
            max_image_dimension_2d: limits.max_image_dimension2_d,
            timestamp_period_ns: limits.timestamp_period,
        }
    }

    /// The physical device's type: what [`RenderPath::Auto`](crate::render::RenderPath)
    /// decides by.
    pub fn device_type(&self) -> vk::PhysicalDeviceType {
        self.device_type
    }

    /// Whether the device's compute shaders have subgroup vote and ballot operations,
    /// which the compute ray caster needs: without them
    /// [`RenderPath::Auto`](crate::render::RenderPath) takes the fragment path, and the
    /// compute path is refused.
    pub fn compute_votes(&self) -> bool {
        self.compute_votes
    }

    /// Whether the device jumps over a branch that no lane of a batch of pixels takes,
    /// which culling by early outs needs to save anything (`Culling::Occluded` takes
    /// them there).
    pub(crate) fn skips_idle_branches(&self) -> bool {
        self.skips_idle_branches
    }

    /// Whether the device has `fragmentStoresAndAtomics` enabled: without it the glyphs
    /// are drawn without culling hidden glyphs and without work counters, from fragment
    /// shaders that write no buffer.
    pub fn fragment_stores(&self) -> bool {
        self.fragment_stores
    }

    /// This context of a host's device that was created with
    /// `fragmentStoresAndAtomics` enabled: the glyph passes may then cull hidden glyphs
    /// (early outs and passes, `RenderSettings::cull`) and count their work. A context
    /// made with [`DeviceContext::new`] or [`DeviceContext::with_memory`] assumes the
    /// feature absent (the component asks a host only for Vulkan 1.3 dynamic rendering),
    /// and draws every glyph as a device without it must.
    ///
    /// # Safety
    /// The device was created with `VkPhysicalDeviceFeatures::fragmentStoresAndAtomics`
    /// enabled; otherwise its fragment shaders' buffer writes are invalid usage.
    pub unsafe fn with_fragment_stores(mut self) -> DeviceContext {
        self.fragment_stores = true;
        self
    }

    /// The pipeline cache every pipeline of this context is created through (null when
    /// there is none): glyphcast's on-disk cache for a device it created
    /// (`vk::pipeline_cache`).
    pub fn pipeline_cache(&self) -> vk::PipelineCache {
        self.owner.pipeline_cache
    }

    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        &self.owner.device
    }

    /// The allocator every buffer and image of this context takes memory from.
    pub fn memory(&self) -> &dyn MemoryAllocator {
        &**self.owner.memory
    }

    /// The device's maxStorageBufferRange: coefficient buffers are split to fit it.
    pub fn max_storage_buffer_range(&self) -> u64 {
        self.max_storage_buffer_range
    }

    /// Components a vertex shader may pass to a fragment shader: the smaller of
    /// maxVertexOutputComponents and maxFragmentInputComponents. The ray-casting passes
    /// hand each glyph's coefficients over as flat inputs, 108 components at order 12.
    pub fn max_varying_components(&self) -> u32 {
        self.max_varying_components
    }

    /// Whether the device blends a float32 colour attachment (R32_SFLOAT), which
    /// culling hidden glyphs needs (render::visibility).
    pub fn blends_float32(&self) -> bool {
        self.blends_float32
    }

    /// The device's maxImageDimension2D: the largest side of an image it draws.
    pub fn max_image_dimension_2d(&self) -> u32 {
        self.max_image_dimension_2d
    }

    /// Nanoseconds per timestamp tick (the device's timestampPeriod).
    pub fn timestamp_period_ns(&self) -> f32 {
        self.timestamp_period_ns
    }

    /// This context with at most `components` varying components, as if the device
    /// had fewer (tests of the limit). Limits can only be lowered: a context never
    /// promises more than the device has.
    pub fn with_max_varying_components(mut self, components: u32) -> DeviceContext {
        self.max_varying_components = self.max_varying_components.min(components);
        self
    }

    /// This context as if its device were of type `device_type`: what
    /// [`RenderPath::Auto`](crate::render::RenderPath) decides by (tests draw a GPU's
    /// choice on lavapipe). Nothing else changes.
    pub fn with_device_type(mut self, device_type: vk::PhysicalDeviceType) -> DeviceContext {
        self.device_type = device_type;
        self
    }

    /// This context as if its device's compute shaders had no subgroup vote and ballot
    /// operations (tests of the fallback on a device that has them).
    pub fn without_compute_votes(mut self) -> DeviceContext {
        self.compute_votes = false;
        self
    }
}

/// A pipeline cache seeded with `file`'s data (empty when there is no file, or when the
/// driver refuses the data); null when none can be made, which only costs time.
fn create_pipeline_cache(
    device: &ash::Device,
    file: Option<&PipelineCacheFile>,
) -> vk::PipelineCache {
    let Some(file) = file else {
        return vk::PipelineCache::null();
    };
    let create = |data: &[u8]| {
        let info = vk::PipelineCacheCreateInfo::default().initial_data(data);
        // SAFETY: valid create info; the data passed `pipeline_cache::parse`'s checks.
        unsafe { device.create_pipeline_cache(&info, None) }
    };
    create(file.initial_data())
        .or_else(|_| create(&[]))
        .unwrap_or(vk::PipelineCache::null())
}

/// Whether a device of this type and driver jumps over a branch that no lane of a batch
/// takes. A GPU does; llvmpipe (lavapipe) runs such code masked in Mesa 22.3 and jumps
/// over it in Mesa 25.0 (measured: a culled 16-layer block 1.6 times faster with early
/// outs on Mesa 25.0, 1.9 times slower on Mesa 22.3, whose passes stay). The Mesa
/// releases between were not measured and keep the passes; another CPU device is taken
/// to run branches masked.
fn skips_idle_branches(
    device_type: vk::PhysicalDeviceType,
    driver: vk::DriverId,
    info: Option<&std::ffi::CStr>,
) -> bool {
    if device_type != vk::PhysicalDeviceType::CPU {
        return true;
    }
    if driver != vk::DriverId::MESA_LLVMPIPE {
        return false;
    }
    // lavapipe's driver info: "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)".
    let major = info
        .and_then(|i| i.to_str().ok())
        .and_then(|i| i.trim().strip_prefix("Mesa "))
        .and_then(|v| v.split('.').next())
        .and_then(|m| m.parse::<u32>().ok());
    major.is_some_and(|m| m >= 25)
}

#[cfg(test)]
mod tests {
    use super::skips_idle_branches;
    use ash::vk;

    #[test]
    fn lavapipe_from_mesa_25_on_and_gpus_take_the_early_outs() {
        let cpu = vk::PhysicalDeviceType::CPU;
        let llvmpipe = vk::DriverId::MESA_LLVMPIPE;
        let info = |text: &'static std::ffi::CStr| Some(text);
        assert!(skips_idle_branches(
            cpu,
            llvmpipe,
            info(c"Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)")
        ));
        assert!(skips_idle_branches(
            cpu,
            llvmpipe,
            info(c"Mesa 26.1.0-devel (git-1a2b3c)")
        ));
        assert!(!skips_idle_branches(
            cpu,
            llvmpipe,
            info(c"Mesa 22.3.6 (LLVM 15.0.6)")
        ));
        assert!(!skips_idle_branches(cpu, llvmpipe, info(c"Mesa 24.2.8")));
        assert!(!skips_idle_branches(cpu, llvmpipe, info(c"unknown")));
        assert!(!skips_idle_branches(cpu, llvmpipe, None));
        assert!(!skips_idle_branches(
            cpu,
            vk::DriverId::GOOGLE_SWIFTSHADER,
            info(c"5.0")
        ));
        let gpu = vk::PhysicalDeviceType::DISCRETE_GPU;
        assert!(skips_idle_branches(
            gpu,
            vk::DriverId::NVIDIA_PROPRIETARY,
            None
        ));
    }
}
