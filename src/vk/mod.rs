//! The thin ash layer: instance and validation, device choice, buffers, images, descriptor
//! sets, pipeline objects that destroy themselves, and one-shot command submission.
//! Nothing here knows about glyphs.
//!
//! [`Gpu`] creates an instance and a device. Headless tools and tests use
//! [`Gpu::headless`]; the viewer uses `Gpu::for_window`, the same construction plus the
//! window system's surface extensions and VK_KHR_swapchain (`Surface`, `Swapchain`; with
//! the feature `window`).
//! An engine that already has a device hands it to the render passes directly (they only
//! need a device and an allocator, see [`DeviceContext`]), so this module never insists
//! on owning the instance.
//!
//! Ownership is shared (`context.rs`): every object made from a device keeps it alive,
//! so dropping the [`Gpu`] before its buffers, images or passes is safe.
mod buffer;
mod commands;
mod context;
mod debug;
mod descriptors;
mod device;
mod image;
mod instance;
pub mod memory;
mod pipeline;
mod pipeline_cache;
pub mod recording;
pub(crate) mod spirv;
#[cfg(feature = "window")]
mod surface;
#[cfg(feature = "window")]
mod swapchain;
mod timer;

pub use buffer::Buffer;
pub use commands::OneShot;
pub use context::DeviceContext;
pub use debug::ValidationLog;
pub use descriptors::{BufferBinding, DescriptorPool};
pub use device::{DeviceInfo, choose_physical_device};
pub use image::{Image, cleared_depth_attachment};
pub use memory::{
    GpuAllocatorMemory, MemoryAllocator, MemoryBlock, MemoryRequest, MemoryUse, default_allocator,
    memory_type_index,
};
pub(crate) use pipeline::specialized_stages;
pub use pipeline::{
    DrawStage, GraphicsPipelineDesc, Pipeline, PipelineLayout, Pipelines, RasterTarget,
    ShaderModule, buffer_binding, compute_pipeline, graphics_pipeline, vertex_fragment_stages,
};
#[cfg(feature = "window")]
pub use surface::Surface;
#[cfg(feature = "window")]
pub use swapchain::{Acquired, Swapchain, color_range};
pub use timer::GpuTimer;

use crate::error::{Error, Result, VkContext};
use ash::vk;
use context::InstanceOwner;
#[cfg(feature = "window")]
use raw_window_handle::RawDisplayHandle;
use std::ffi::{CStr, c_char};
use std::sync::Arc;

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

    /// These options with a front end's on top: `device` if given, and validation if
    /// `validation` (the environment's stays on otherwise).
    pub fn with(mut self, device: Option<String>, validation: bool) -> Self {
        self.validation |= validation;
        if device.is_some() {
            self.device = device;
        }
        self
    }
}

/// An instance, one device with a graphics+compute queue, and a memory allocator.
/// Buffers, images and passes made from it keep the device (and the instance) alive, so
/// the `Gpu` may be dropped before them; the last one destroys the device.
pub struct Gpu {
    /// The chosen physical device.
    pub physical_device: vk::PhysicalDevice,
    /// The graphics+compute queue every submit goes to.
    pub queue: vk::Queue,
    /// The queue's family index.
    pub queue_family: u32,
    /// What the device is, for printing and reports.
    pub info: DeviceInfo,
    /// Shares the device with everything made from it; the last holder destroys it.
    context: DeviceContext,
    /// Shared with the device's owner and the window surfaces in the same way.
    instance: Arc<InstanceOwner>,
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
    #[cfg(feature = "window")]
    pub fn for_window(options: &GpuOptions, display: RawDisplayHandle) -> Result<Gpu> {
        let surface_extensions =
            ash_window::enumerate_required_extensions(display).map_err(|result| {
                Error::setup("Vulkan surface support for this window system", result)
            })?;
        Gpu::create(options, surface_extensions, &[ash::khr::swapchain::NAME])
    }

    fn create(
        options: &GpuOptions,
        surface_extensions: &[*const c_char],
        device_extensions: &[&CStr],
    ) -> Result<Gpu> {
        // The loader is opened here, not linked: a program or Python module built with
        // glyphcast starts and imports without it, and the first render says what to
        // install (the name is Debian's and Ubuntu's, then Fedora's and RHEL's).
        // SAFETY: loading the Vulkan loader library has no preconditions beyond the
        // library itself being a conforming loader.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| {
            Error::setup(
                "Vulkan loader, libvulkan.so.1 (install libvulkan1, or vulkan-loader on \
                 Fedora and RHEL)",
                e,
            )
        })?;
        let log = ValidationLog::default();
        let (instance, messenger) =
            instance::create(&entry, options.validation, &log, surface_extensions)?;
        let validation = messenger.map(|handle| debug::Messenger {
            loader: ash::ext::debug_utils::Instance::new(&entry, &instance),
            handle,
            log,
        });
        let instance_owner = Arc::new(InstanceOwner {
            entry,
            instance,
            validation,
        });
        let instance = &instance_owner.instance;
        let (physical_device, info) =
            device::choose_with_extensions(instance, options.device.as_deref(), device_extensions)?;
        let (device, queue_family) = device::create(instance, physical_device, device_extensions)?;
        let allocator = memory::default_allocator(instance, &device, physical_device);
        let allocator = match allocator {
            Ok(allocator) => allocator,
            Err(e) => {
                // SAFETY: nothing was created from the device yet.
                unsafe { device.destroy_device(None) };
                return Err(e.into());
            }
        };
        // SAFETY: the queue family was requested with one queue when the device was created.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let context =
            DeviceContext::created(instance_owner.clone(), physical_device, device, allocator);
        Ok(Gpu {
            physical_device,
            queue,
            queue_family,
            info,
            context,
            instance: instance_owner,
        })
    }

    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        self.context.device()
    }

    /// The Vulkan instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.instance.instance
    }

    /// The loaded Vulkan entry points.
    pub fn entry(&self) -> &ash::Entry {
        &self.instance.entry
    }

    /// The instance's owner, for objects made from the instance (window surfaces).
    #[cfg(feature = "window")]
    pub(crate) fn instance_owner(&self) -> &Arc<InstanceOwner> {
        &self.instance
    }

    /// Device, allocator and limits, for buffers, images and passes.
    pub fn context(&self) -> &DeviceContext {
        &self.context
    }

    /// Validation errors reported so far (empty when validation is off).
    pub fn validation_errors(&self) -> Vec<String> {
        self.validation_log()
            .map(|log| log.errors())
            .unwrap_or_default()
    }

    /// A handle to the validation errors that stays readable after the `Gpu` is dropped
    /// (errors raised while the objects that outlive it are destroyed arrive there too);
    /// `None` when validation is off.
    pub fn validation_log(&self) -> Option<ValidationLog> {
        self.instance.validation.as_ref().map(|m| m.log.clone())
    }

    /// Whether the validation layer is on.
    pub fn validation_enabled(&self) -> bool {
        self.instance.validation.is_some()
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

    /// Waits until the device has finished all submitted work.
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: the device is alive for as long as the context `self` holds.
        unsafe { self.device().device_wait_idle() }.vk("vkDeviceWaitIdle")
    }
}
