//! The swapchain of a window's surface: format and size choice, image views, and the
//! acquire/present calls with their out-of-date results turned into values, so that the
//! caller recreates the swapchain instead of rendering into a stale one.
//!
//! Each image has its own "rendering finished" semaphore: a present's wait on it is only
//! known to be over when that image is acquired again, so one semaphore shared by all
//! images could be signalled again while a present still waits on it.
//!
//! A swapchain keeps its device (through a [`DeviceContext`]) and its surface alive.
use super::DeviceContext;
use super::surface::{Surface, SurfaceOwner};
use crate::error::{Result, VkContext};
use ash::vk;
use std::sync::Arc;

/// A window's swapchain with a view and a "rendering finished" semaphore per image; it
/// keeps its device and surface alive and destroys its objects on drop.
pub struct Swapchain {
    /// The raw swapchain, for vkQueuePresentKHR.
    pub handle: vk::SwapchainKHR,
    /// The images' format: an sRGB format where the surface offers one.
    pub format: vk::Format,
    /// The images' size in pixels.
    pub extent: vk::Extent2D,
    /// The swapchain's images, owned by it (not destroyed separately).
    pub images: Vec<vk::Image>,
    /// One colour view per image, in the order of `images`.
    pub views: Vec<vk::ImageView>,
    /// Per image: signalled by the submission that renders it, waited on by its present.
    pub render_finished: Vec<vk::Semaphore>,
    /// The images can be copied from (TRANSFER_SRC), to read back what the window shows.
    pub readable: bool,
    /// The images can be copied into (TRANSFER_DST): the viewer copies montage panels
    /// and the colour bar's strip into them.
    pub writable: bool,
    loader: ash::khr::swapchain::Device,
    ctx: DeviceContext,
    /// Destroyed after the swapchain (after `Drop::drop` runs).
    _surface: Arc<SurfaceOwner>,
}

/// What vkAcquireNextImageKHR gave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Acquired {
    /// An image to render.
    Image {
        /// Index of the acquired image in the swapchain's `images`.
        index: u32,
        /// The image still works, but the swapchain no longer matches the surface
        /// exactly: recreate it after presenting.
        suboptimal: bool,
    },
    /// The surface changed (resize): recreate before rendering.
    OutOfDate,
}

/// sRGB formats first: the ray caster writes linear colour, as into the headless target.
fn choose_format(formats: &[vk::SurfaceFormatKHR]) -> Option<vk::SurfaceFormatKHR> {
    let srgb = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];
    formats
        .iter()
        .find(|f| srgb.contains(&f.format) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
        .or_else(|| formats.first())
        .copied()
}

/// FIFO (always there, paced by the display) unless `unthrottled` asks for IMMEDIATE or
/// MAILBOX where the surface has one (scripted runs that should not wait for vsync).
fn choose_present_mode(modes: &[vk::PresentModeKHR], unthrottled: bool) -> vk::PresentModeKHR {
    let fast = [vk::PresentModeKHR::IMMEDIATE, vk::PresentModeKHR::MAILBOX];
    fast.into_iter()
        .find(|m| unthrottled && modes.contains(m))
        .unwrap_or(vk::PresentModeKHR::FIFO)
}

impl Swapchain {
    /// A swapchain of about `wanted` (the window's inner size; the surface's own extent
    /// wins where it has one), replacing `old` if given. `None` while the surface has no
    /// area (a minimised window): there is nothing to render into.
    pub fn new(
        gpu: &super::Gpu,
        surface: &Surface,
        wanted: vk::Extent2D,
        unthrottled: bool,
        old: Option<&Swapchain>,
    ) -> Result<Option<Swapchain>> {
        let (pd, s) = (gpu.physical_device, surface.handle());
        let surface_loader = &surface.owner().loader;
        // SAFETY: the surface belongs to the Gpu's instance; `pd` is the Gpu's device.
        let (caps, formats, modes) = unsafe {
            (
                surface_loader
                    .get_physical_device_surface_capabilities(pd, s)
                    .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                surface_loader
                    .get_physical_device_surface_formats(pd, s)
                    .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?,
                surface_loader
                    .get_physical_device_surface_present_modes(pd, s)
                    .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?,
            )
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: wanted
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: wanted
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let Some(format) = choose_format(&formats) else {
            return Err(crate::Error::Setup {
                missing: "surface format",
                found: None,
            });
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let readable = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let writable = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST);
        let mut usage = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        if readable {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        if writable {
            usage |= vk::ImageUsageFlags::TRANSFER_DST;
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|a| caps.supported_composite_alpha.contains(*a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(s)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(choose_present_mode(&modes, unthrottled))
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.handle));
        let loader = ash::khr::swapchain::Device::new(gpu.instance(), gpu.device());
        // SAFETY: the create info is complete; the old swapchain (if any) is retired by
        // this call and destroyed by its owner afterwards.
        let handle = unsafe { loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        let mut swapchain = Swapchain {
            handle,
            format: format.format,
            extent,
            images: Vec::new(),
            views: Vec::new(),
            render_finished: Vec::new(),
            readable,
            writable,
            loader,
            ctx: gpu.context().clone(),
            _surface: surface.owner().clone(),
        };
        swapchain.create_views()?;
        Ok(Some(swapchain))
    }

    fn create_views(&mut self) -> Result<()> {
        // SAFETY: the swapchain was created from this device.
        self.images = unsafe { self.loader.get_swapchain_images(self.handle) }
            .vk("vkGetSwapchainImagesKHR")?;
        for &image in &self.images {
            let info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(self.format)
                .subresource_range(color_range());
            // SAFETY: the image belongs to the swapchain, which outlives its views.
            let view = unsafe { self.ctx.device().create_image_view(&info, None) }
                .vk("vkCreateImageView")?;
            self.views.push(view);
            // SAFETY: valid device; destroyed in Drop.
            let semaphore = unsafe {
                self.ctx
                    .device()
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            }
            .vk("vkCreateSemaphore")?;
            self.render_finished.push(semaphore);
        }
        Ok(())
    }

    /// The next image to render into; `signal` is signalled when it may be written.
    pub fn acquire(&self, signal: vk::Semaphore) -> Result<Acquired> {
        // SAFETY: `signal` is unsignalled with no pending operation (the caller waited
        // for the frame that last used it).
        let result = unsafe {
            self.loader
                .acquire_next_image(self.handle, u64::MAX, signal, vk::Fence::null())
        };
        // vkAcquireNextImageKHR may fail with OUT_OF_HOST/DEVICE_MEMORY, DEVICE_LOST,
        // OUT_OF_DATE_KHR, SURFACE_LOST_KHR and FULL_SCREEN_EXCLUSIVE_MODE_LOST_EXT; only
        // OUT_OF_DATE is a normal event (the window changed), the rest are failures.
        match result {
            Ok((index, suboptimal)) => Ok(Acquired::Image { index, suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(result) => Err(crate::Error::Vulkan {
                call: "vkAcquireNextImageKHR",
                result,
            }),
        }
    }

    /// Presents image `index` once its `render_finished` semaphore is signalled. Returns
    /// false when the swapchain no longer fits the surface (SUBOPTIMAL or OUT_OF_DATE).
    pub fn present(&self, queue: vk::Queue, index: u32) -> Result<bool> {
        let wait = [self.render_finished[index as usize]];
        let swapchains = [self.handle];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and a submission that signals `wait` was made.
        let result = unsafe { self.loader.queue_present(queue, &info) };
        // vkQueuePresentKHR may fail with OUT_OF_HOST/DEVICE_MEMORY, DEVICE_LOST,
        // OUT_OF_DATE_KHR, SURFACE_LOST_KHR and FULL_SCREEN_EXCLUSIVE_MODE_LOST_EXT.
        match result {
            Ok(suboptimal) => Ok(!suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(result) => Err(crate::Error::Vulkan {
                call: "vkQueuePresentKHR",
                result,
            }),
        }
    }
}

/// The one mip level and layer of a colour image.
pub fn color_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the owner waited for the device to be idle, so no submission or present
        // uses the views, semaphores or images. The device and the surface are alive
        // while `self.ctx` and `self._surface` are.
        unsafe {
            for &view in &self.views {
                device.destroy_image_view(view, None);
            }
            for &semaphore in &self.render_finished {
                device.destroy_semaphore(semaphore, None);
            }
            self.loader.destroy_swapchain(self.handle, None);
        }
    }
}
