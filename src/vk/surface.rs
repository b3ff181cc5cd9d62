//! A window's Vulkan surface (through ash-window, which picks the platform's
//! vkCreate*SurfaceKHR from the raw window handles), checked for presentation support on
//! the [`Gpu`](super::Gpu)'s queue. The surface keeps the instance alive, and each
//! [`Swapchain`](super::Swapchain) made from it keeps the surface alive.
use super::context::InstanceOwner;
use crate::error::{Error, Result, VkContext};
use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};
use std::sync::Arc;

/// A window's `VkSurfaceKHR`, checked to be presentable from the device's queue; swapchains
/// made from it keep it alive.
pub struct Surface {
    owner: Arc<SurfaceOwner>,
}

/// The surface handle and what destroys it, shared by the [`Surface`] and its swapchains.
pub(crate) struct SurfaceOwner {
    pub handle: vk::SurfaceKHR,
    pub loader: ash::khr::surface::Instance,
    /// Keeps the instance alive until the surface is destroyed.
    _instance: Arc<InstanceOwner>,
}

impl Surface {
    /// Creates the surface of a window and checks that the Gpu's queue can present to it.
    ///
    /// # Safety
    /// The handles must belong to a live window, and the window must outlive the surface
    /// and every swapchain made from it; the Gpu must come from
    /// [`Gpu::for_window`](super::Gpu::for_window) with the same display.
    pub unsafe fn new(
        gpu: &super::Gpu,
        display: RawDisplayHandle,
        window: RawWindowHandle,
    ) -> Result<Surface> {
        // SAFETY: the caller vouches for the handles; the instance has the extensions
        // ash_window asked for when the Gpu was created for this display.
        let handle = unsafe {
            ash_window::create_surface(gpu.entry(), gpu.instance(), display, window, None)
        }
        .vk("vkCreate*SurfaceKHR")?;
        let surface = Surface {
            owner: Arc::new(SurfaceOwner {
                handle,
                loader: ash::khr::surface::Instance::new(gpu.entry(), gpu.instance()),
                _instance: gpu.instance_owner().clone(),
            }),
        };
        // SAFETY: the queue family index is the Gpu's, the surface was just created.
        let supported = unsafe {
            surface.owner.loader.get_physical_device_surface_support(
                gpu.physical_device,
                gpu.queue_family,
                handle,
            )
        }
        .vk("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(Error::setup(
                "presentation to this window from the graphics queue",
                &gpu.info.name,
            ));
        }
        Ok(surface)
    }

    /// The raw surface handle, valid while this `Surface` (or a swapchain of it) lives.
    pub fn handle(&self) -> vk::SurfaceKHR {
        self.owner.handle
    }

    /// The shared owner, for a swapchain to keep.
    pub(crate) fn owner(&self) -> &Arc<SurfaceOwner> {
        &self.owner
    }
}

impl Drop for SurfaceOwner {
    fn drop(&mut self) {
        // SAFETY: the swapchains made from the surface hold this owner, so they are gone;
        // the instance is alive while `_instance` is, which drops after this body. The
        // window outlives the surface (the caller's promise in `Surface::new`).
        unsafe { self.loader.destroy_surface(self.handle, None) };
    }
}
