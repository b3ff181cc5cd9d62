//! A window's Vulkan surface (through ash-window, which picks the platform's
//! vkCreate*SurfaceKHR from the raw window handles), checked for presentation support on
//! the [`Gpu`](super::Gpu)'s queue.
use crate::error::{Error, Result, VkContext};
use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

pub struct Surface {
    pub handle: vk::SurfaceKHR,
    pub(crate) loader: ash::khr::surface::Instance,
}

impl Surface {
    /// Creates the surface of a window and checks that the Gpu's queue can present to it.
    ///
    /// # Safety
    /// The handles must belong to a live window, and the window must outlive the surface;
    /// the Gpu must come from [`Gpu::for_window`](super::Gpu::for_window) with the same
    /// display and outlive the surface.
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
            handle,
            loader: ash::khr::surface::Instance::new(gpu.entry(), gpu.instance()),
        };
        // SAFETY: the queue family index is the Gpu's, the surface was just created.
        let supported = unsafe {
            surface.loader.get_physical_device_surface_support(
                gpu.physical_device,
                gpu.queue_family,
                handle,
            )
        }
        .vk("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(Error::Setup(format!(
                "the graphics queue of {} cannot present to this window",
                gpu.info.name
            )));
        }
        Ok(surface)
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: the swapchains made from the surface are gone (the owner drops them
        // first) and the instance is alive (the caller's promise in `new`).
        unsafe { self.loader.destroy_surface(self.handle, None) };
    }
}
