//! The engine's side of the example, in plain ash and gpu-allocator: its own instance
//! (with the validation layer and a debug messenger that keeps the errors), device,
//! queue, allocator, command pool, images and readback buffers. Nothing here comes from
//! glyphcast; this is what an engine has before it adds glyphs.
use super::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use std::ffi::{CStr, c_void};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Validation errors and warnings, filled by the debug messenger.
type Messages = Mutex<Vec<String>>;

pub struct Engine {
    pub instance: ash::Instance,
    pub physical_device: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue: vk::Queue,
    #[cfg_attr(not(test), allow(dead_code))]
    family: u32,
    /// Dropped by hand in `Drop`: its memory must be freed before the device goes.
    allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    pool: vk::CommandPool,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    messages: Arc<Messages>,
    _entry: ash::Entry,
}

/// An image with its memory and one view.
pub struct Target {
    pub image: vk::Image,
    pub view: vk::ImageView,
    allocation: Allocation,
}

/// A host-visible buffer to copy an image into.
pub struct Readback {
    pub buffer: vk::Buffer,
    allocation: Allocation,
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid data for the call; `user` is the engine's Messages,
    // which the engine keeps alive until the messenger is destroyed.
    let (data, messages) = unsafe { (&*data, &*(user as *const Messages)) };
    // SAFETY: the layer's message is a NUL-terminated string.
    let text = unsafe { data.message_as_c_str() }
        .map_or_else(String::new, |m| m.to_string_lossy().into_owned());
    let level = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        "error"
    } else {
        "warning"
    };
    eprintln!("validation {level}: {text}");
    if let Ok(mut list) = messages.lock() {
        list.push(format!("{level}: {text}"));
    }
    vk::FALSE
}

/// How the engine runs the validation layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Validation {
    Off,
    /// The layer's core checks.
    On,
    /// The core checks and synchronization validation
    /// (VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT).
    Sync,
}

impl Engine {
    /// Instance, first Vulkan 1.3 device with dynamic rendering (and sample-rate shading,
    /// which glyphcast's multisampled glyphs need; fragmentStoresAndAtomics too where
    /// `fragment_stores`), one graphics queue.
    pub fn new(validation: Validation, fragment_stores: bool) -> Result<Engine> {
        // SAFETY: loading the system's Vulkan loader.
        let entry = unsafe { ash::Entry::load()? };
        let messages = Arc::new(Messages::default());
        let app = vk::ApplicationInfo::default()
            .application_name(c"glyphcast embed example")
            .api_version(vk::API_VERSION_1_3);
        let layers = [VALIDATION_LAYER.as_ptr()];
        let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
        let sync = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync);
        let mut info = vk::InstanceCreateInfo::default().application_info(&app);
        if validation != Validation::Off {
            info = info
                .enabled_layer_names(&layers)
                .enabled_extension_names(&extensions);
        }
        if validation == Validation::Sync {
            info = info.push_next(&mut features);
        }
        let validation = validation != Validation::Off;
        // SAFETY: every pointer in `info` outlives the call.
        let instance = unsafe { entry.create_instance(&info, None)? };
        let messenger = validation
            .then(|| {
                let loader = ash::ext::debug_utils::Instance::new(&entry, &instance);
                let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                    .message_severity(
                        vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                            | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
                    )
                    .message_type(
                        vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                            | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                    )
                    .pfn_user_callback(Some(on_message))
                    .user_data(Arc::as_ptr(&messages) as *mut c_void);
                // SAFETY: the instance has VK_EXT_debug_utils.
                unsafe { loader.create_debug_utils_messenger(&info, None) }.map(|m| (loader, m))
            })
            .transpose()?;
        let (physical_device, family) = pick_device(&instance)?;
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        // What glyphcast's passes need of a device: Vulkan 1.3 dynamic rendering.
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true);
        // And of Vulkan 1.0: sample-rate shading for MSAA targets, and, where the engine
        // wants hidden glyphs culled, storage writes in fragment shaders.
        let core = vk::PhysicalDeviceFeatures::default()
            .sample_rate_shading(true)
            .fragment_stores_and_atomics(fragment_stores);
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&core)
            .push_next(&mut v13);
        // SAFETY: the features were checked in `pick_device`.
        let device = unsafe { instance.create_device(physical_device, &info, None)? };
        // SAFETY: one queue of this family was requested.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device.
        let pool = unsafe { device.create_command_pool(&pool_info, None)? };
        Ok(Engine {
            instance,
            physical_device,
            device,
            queue,
            family,
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            pool,
            messenger,
            messages,
            _entry: entry,
        })
    }

    /// The engine's allocator, shared with glyphcast through its DeviceContext.
    pub fn allocator(&self) -> Arc<Mutex<Allocator>> {
        Arc::clone(&self.allocator)
    }

    /// Validation messages so far (errors and warnings).
    pub fn validation_messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    pub fn create_image(
        &self,
        name: &str,
        extent: vk::Extent2D,
        format: (vk::Format, vk::SampleCountFlags),
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Target> {
        let (format, samples) = format;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(extent.into())
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: complete create info; destroyed in `destroy_image`.
        let image = unsafe { self.device.create_image(&info, None)? };
        // SAFETY: `image` belongs to this device.
        let requirements = unsafe { self.device.get_image_memory_requirements(image) };
        let allocation = self.allocate(name, requirements, MemoryLocation::GpuOnly, false)?;
        let range = subresource_range(aspect);
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(range);
        // SAFETY: memory bound right after allocation; compatible view.
        let view = unsafe {
            self.device
                .bind_image_memory(image, allocation.memory(), allocation.offset())?;
            self.device.create_image_view(&view_info, None)?
        };
        Ok(Target {
            image,
            view,
            allocation,
        })
    }

    pub fn destroy_image(&self, target: Target) -> Result<()> {
        // SAFETY: the frame that used the image has completed.
        unsafe {
            self.device.destroy_image_view(target.view, None);
            self.device.destroy_image(target.image, None);
        }
        self.free(target.allocation)
    }

    pub fn create_readback(&self, name: &str, size: u64) -> Result<Readback> {
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(vk::BufferUsageFlags::TRANSFER_DST);
        // SAFETY: complete create info; destroyed in `destroy_readback`.
        let buffer = unsafe { self.device.create_buffer(&info, None)? };
        // SAFETY: `buffer` belongs to this device.
        let requirements = unsafe { self.device.get_buffer_memory_requirements(buffer) };
        let allocation = self.allocate(name, requirements, MemoryLocation::GpuToCpu, true)?;
        // SAFETY: fresh allocation satisfying the requirements.
        unsafe {
            self.device
                .bind_buffer_memory(buffer, allocation.memory(), allocation.offset())?
        };
        Ok(Readback { buffer, allocation })
    }

    /// The bytes of a readback buffer after the copy into it completed.
    pub fn read<'a>(&self, readback: &'a Readback) -> Result<&'a [u8]> {
        Ok(readback
            .allocation
            .mapped_slice()
            .ok_or("readback memory is not mapped")?)
    }

    pub fn destroy_readback(&self, readback: Readback) -> Result<()> {
        // SAFETY: the copy into the buffer has completed.
        unsafe { self.device.destroy_buffer(readback.buffer, None) };
        self.free(readback.allocation)
    }

    fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> Result<Allocation> {
        let mut allocator = self.allocator.lock().map_err(|_| "allocator poisoned")?;
        Ok(allocator.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?)
    }

    fn free(&self, allocation: Allocation) -> Result<()> {
        let mut allocator = self.allocator.lock().map_err(|_| "allocator poisoned")?;
        Ok(allocator.free(allocation)?)
    }

    /// A command pool of the engine's queue family for one recording thread (command
    /// pools are externally synchronised); the caller destroys it.
    #[cfg(test)]
    pub fn create_command_pool(&self) -> Result<vk::CommandPool> {
        let info = vk::CommandPoolCreateInfo::default().queue_family_index(self.family);
        // SAFETY: valid device and family.
        Ok(unsafe { self.device.create_command_pool(&info, None)? })
    }

    /// Command buffers from the engine's pool, one per frame in flight.
    pub fn command_buffers(&self, count: u32) -> Result<Vec<vk::CommandBuffer>> {
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count);
        // SAFETY: the pool belongs to this device (created resettable); the buffers go
        // with the pool.
        Ok(unsafe { self.device.allocate_command_buffers(&alloc)? })
    }
}

pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// The first Vulkan 1.3 device with dynamic rendering and a graphics queue.
fn pick_device(instance: &ash::Instance) -> Result<(vk::PhysicalDevice, u32)> {
    // SAFETY: valid instance.
    for pd in unsafe { instance.enumerate_physical_devices()? } {
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut v13);
        // SAFETY: `pd` comes from this instance.
        let (api, families) = unsafe {
            instance.get_physical_device_features2(pd, &mut features);
            (
                instance.get_physical_device_properties(pd).api_version,
                instance.get_physical_device_queue_family_properties(pd),
            )
        };
        let family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS));
        // SAFETY: `pd` comes from this instance.
        let core = unsafe { instance.get_physical_device_features(pd) };
        if let Some(family) = family
            && core.sample_rate_shading == vk::TRUE
            && core.fragment_stores_and_atomics == vk::TRUE
            && api >= vk::API_VERSION_1_3
            && v13.dynamic_rendering == vk::TRUE
            && v13.synchronization2 == vk::TRUE
        {
            return Ok((pd, family as u32));
        }
    }
    Err("no Vulkan 1.3 device with dynamic rendering".into())
}

impl Drop for Engine {
    fn drop(&mut self) {
        // SAFETY: everything created from the device (glyphcast's pass and buffers, the
        // engine's images) was dropped before the engine; the allocator goes with its
        // last handle, before the device.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((loader, messenger)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
