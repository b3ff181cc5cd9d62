//! The thin ash layer: instance and validation, device choice, buffers, images and
//! one-shot command submission. Nothing here knows about glyphs.
//!
//! [`Gpu`] owns what it created. Headless tools and tests use [`Gpu::headless`]; the
//! viewer uses [`Gpu::for_window`], the same construction plus the window system's surface
//! extensions and VK_KHR_swapchain ([`Surface`], [`Swapchain`]). An engine that already
//! has a device hands it to the render passes directly (they only need an `ash::Device`
//! and an allocator, see [`DeviceContext`]), so this module never insists on owning the
//! instance.
mod buffer;
mod commands;
mod debug;
mod device;
mod image;
mod instance;
mod surface;
mod swapchain;
mod timer;

pub use buffer::Buffer;
pub use commands::OneShot;
pub use debug::ValidationLog;
pub use device::{DeviceInfo, choose_physical_device};
pub use image::{Image, cleared_depth_attachment};
pub use surface::Surface;
pub use swapchain::{Acquired, Swapchain, color_range};
pub use timer::GpuTimer;

use crate::error::{Error, Result, VkContext};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use raw_window_handle::RawDisplayHandle;
use std::ffi::{CStr, c_char};
use std::sync::{Arc, Mutex};

/// What to ask of [`Gpu::headless`].
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Load VK_LAYER_KHRONOS_validation and collect its errors (always on in tests).
    pub validation: bool,
    /// Pick the device whose name contains this text (case-insensitive), or by index.
    pub device: Option<String>,
}

impl GpuOptions {
    /// Options from the environment: GLYPHCAST_VALIDATION=1 turns validation on,
    /// GLYPHCAST_DEVICE names the device.
    pub fn from_env() -> Self {
        GpuOptions {
            validation: std::env::var("GLYPHCAST_VALIDATION").is_ok_and(|v| v != "0"),
            device: std::env::var("GLYPHCAST_DEVICE")
                .ok()
                .filter(|v| !v.is_empty()),
        }
    }
}

/// Owns the instance and the debug messenger; destroys them last.
struct InstanceOwner {
    entry: ash::Entry,
    instance: ash::Instance,
    validation: Option<debug::Messenger>,
}

impl Drop for InstanceOwner {
    fn drop(&mut self) {
        // SAFETY: the device owner is declared before this field in `Gpu`, so every
        // child object is gone by the time the instance is destroyed.
        unsafe {
            if let Some(m) = &self.validation {
                m.loader.destroy_debug_utils_messenger(m.handle, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// Owns the logical device; the allocator's memory must be freed before it goes.
struct DeviceOwner {
    device: ash::Device,
    allocator: Option<Arc<Mutex<Allocator>>>,
}

impl Drop for DeviceOwner {
    fn drop(&mut self) {
        // SAFETY: objects created from the device borrow the `Gpu`, so they are gone;
        // after waiting for idle the allocator frees its blocks and the device can go.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.allocator = None;
            self.device.destroy_device(None);
        }
    }
}

/// What buffers, images and render passes need of a device: the device, an allocator
/// for it, and its limits. [`Gpu`] makes one for itself; an engine that owns its Vulkan
/// device builds one around its own objects with [`DeviceContext::new`], and glyphcast
/// then creates no instance or device of its own.
#[derive(Clone)]
pub struct DeviceContext {
    pub device: ash::Device,
    pub allocator: Arc<Mutex<Allocator>>,
    /// The device's maxStorageBufferRange: coefficient buffers are split to fit it.
    pub max_storage_buffer_range: u64,
    /// Components a vertex shader may pass to a fragment shader: the smaller of
    /// maxVertexOutputComponents and maxFragmentInputComponents. The ray-casting passes
    /// hand each glyph's coefficients over as flat inputs, 108 components at order 12.
    pub max_varying_components: u32,
}

impl DeviceContext {
    /// Wraps a caller's device and allocator; the limits are read from `physical_device`.
    pub fn new(
        instance: &ash::Instance,
        physical_device: vk::PhysicalDevice,
        device: ash::Device,
        allocator: Arc<Mutex<Allocator>>,
    ) -> DeviceContext {
        // SAFETY: the caller's physical device belongs to the caller's instance.
        let limits = unsafe { instance.get_physical_device_properties(physical_device) }.limits;
        DeviceContext {
            device,
            allocator,
            max_storage_buffer_range: limits.max_storage_buffer_range as u64,
            max_varying_components: limits
                .max_vertex_output_components
                .min(limits.max_fragment_input_components),
        }
    }
}

/// An instance, one device with a graphics+compute queue, and a memory allocator.
pub struct Gpu {
    pub physical_device: vk::PhysicalDevice,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub info: DeviceInfo,
    // Declaration order is drop order: the context's allocator handle, then the device
    // (which frees the allocator's memory first), then the instance.
    context: DeviceContext,
    device_owner: DeviceOwner,
    instance_owner: InstanceOwner,
}

impl Gpu {
    /// Creates everything needed to render offscreen, with no window system.
    pub fn headless(options: &GpuOptions) -> Result<Gpu> {
        Gpu::create(options, &[], &[])
    }

    /// As [`Gpu::headless`], plus what presenting to windows of `display` needs: the
    /// window system's surface extensions on the instance and VK_KHR_swapchain on the
    /// device (devices without it are passed over). Whether the queue can present to a
    /// particular window is checked when its [`Surface`] is created.
    pub fn for_window(options: &GpuOptions, display: RawDisplayHandle) -> Result<Gpu> {
        let surface_extensions =
            ash_window::enumerate_required_extensions(display).map_err(|result| {
                Error::Setup(format!(
                    "no Vulkan surface support for this window system ({result})"
                ))
            })?;
        Gpu::create(options, surface_extensions, &[ash::khr::swapchain::NAME])
    }

    fn create(
        options: &GpuOptions,
        surface_extensions: &[*const c_char],
        device_extensions: &[&CStr],
    ) -> Result<Gpu> {
        // SAFETY: loading the Vulkan loader library has no preconditions beyond the
        // library itself being a conforming loader.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| {
            Error::Setup(format!(
                "cannot load the Vulkan loader (libvulkan.so.1): {e}"
            ))
        })?;
        let log = ValidationLog::default();
        let (instance, messenger) =
            instance::create(&entry, options.validation, &log, surface_extensions)?;
        let validation = messenger.map(|handle| debug::Messenger {
            loader: ash::ext::debug_utils::Instance::new(&entry, &instance),
            handle,
            log,
        });
        let instance_owner = InstanceOwner {
            entry,
            instance,
            validation,
        };
        let instance = &instance_owner.instance;
        let (physical_device, info) =
            device::choose_with_extensions(instance, options.device.as_deref(), device_extensions)?;
        let (device, queue_family) = device::create(instance, physical_device, device_extensions)?;
        let mut device_owner = DeviceOwner {
            device,
            allocator: None,
        };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device_owner.device.clone(),
            physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        let allocator = Arc::new(Mutex::new(allocator));
        device_owner.allocator = Some(allocator.clone());
        let context = DeviceContext::new(
            instance,
            physical_device,
            device_owner.device.clone(),
            allocator,
        );
        // SAFETY: the queue family was requested with one queue when the device was created.
        let queue = unsafe { device_owner.device.get_device_queue(queue_family, 0) };
        Ok(Gpu {
            physical_device,
            queue,
            queue_family,
            info,
            context,
            device_owner,
            instance_owner,
        })
    }

    pub fn device(&self) -> &ash::Device {
        &self.device_owner.device
    }

    pub fn instance(&self) -> &ash::Instance {
        &self.instance_owner.instance
    }

    pub fn entry(&self) -> &ash::Entry {
        &self.instance_owner.entry
    }

    /// Device, allocator and limits, for buffers, images and passes.
    pub fn context(&self) -> &DeviceContext {
        &self.context
    }

    /// Validation errors reported so far (empty when validation is off).
    pub fn validation_errors(&self) -> Vec<String> {
        self.instance_owner
            .validation
            .as_ref()
            .map(|m| m.log.errors())
            .unwrap_or_default()
    }

    pub fn validation_enabled(&self) -> bool {
        self.instance_owner.validation.is_some()
    }

    /// Fails with [`Error::Validation`] if the validation layer reported any error.
    pub fn check_validation(&self) -> Result<()> {
        let errors = self.validation_errors();
        if errors.is_empty() {
            Ok(())
        } else {
            Err(Error::Validation(errors))
        }
    }

    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: the device is alive for as long as `self`.
        unsafe { self.device().device_wait_idle() }.vk("vkDeviceWaitIdle")
    }
}
