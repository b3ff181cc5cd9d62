//! Offscreen 2D images (colour and depth targets) whose memory comes from the context's
//! [`MemoryAllocator`](super::MemoryAllocator). An image keeps its [`DeviceContext`], so
//! the device outlives it.
use super::DeviceContext;
use super::buffer::checked_block;
use super::memory::{MemoryBlock, MemoryRequest, MemoryUse};
use crate::error::{Error, Result, VkContext};
use ash::vk;

/// A device-local 2D image (one mip level, one layer) with its view; freed on drop.
pub struct Image {
    /// The Vulkan image.
    pub handle: vk::Image,
    /// A 2D view of the whole image.
    pub view: vk::ImageView,
    /// Its pixel format.
    pub format: vk::Format,
    /// Its size, pixels.
    pub extent: vk::Extent2D,
    /// Colour or depth, as its view and barriers see it.
    pub aspect: vk::ImageAspectFlags,
    block: Option<MemoryBlock>,
    ctx: DeviceContext,
}

impl Image {
    /// An optimal-tiling image of `extent` and `format` with `usage`, and its view of
    /// `aspect`; `name` labels the allocation and out-of-memory errors.
    pub fn new(
        ctx: &DeviceContext,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Image> {
        let device = ctx.device();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: `info` is complete; the device is alive.
        let handle =
            unsafe { device.create_image(&info, None) }.map_err(|result| match result {
                vk::Result::ERROR_OUT_OF_HOST_MEMORY | vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => {
                    Error::OutOfMemory {
                        what: "a device image",
                        file: None,
                        bytes: Some(4 * u64::from(extent.width) * u64::from(extent.height)),
                        settings: &[],
                    }
                }
                result => Error::Vulkan {
                    call: "vkCreateImage",
                    result,
                },
            })?;
        let mut image = Image {
            handle,
            view: vk::ImageView::null(),
            format,
            extent,
            aspect,
            block: None,
            ctx: ctx.clone(),
        };
        // SAFETY: `handle` was created from this device.
        let requirements = unsafe { device.get_image_memory_requirements(handle) };
        let usage = MemoryUse::DeviceLocal;
        let block = ctx.memory().allocate(&MemoryRequest {
            name,
            requirements,
            usage,
            linear: false,
        })?;
        let block = checked_block(ctx, name, block, &requirements, usage)?;
        let (memory, offset) = (block.memory, block.offset);
        // From here on, dropping the image gives the block back.
        image.block = Some(block);
        // SAFETY: the block satisfies the image's requirements (checked above).
        unsafe { device.bind_image_memory(handle, memory, offset) }.vk("vkBindImageMemory")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(handle)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(image.subresource_range());
        // SAFETY: the image has memory bound and a compatible format.
        image.view =
            unsafe { device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        Ok(image)
    }

    /// The whole image (its one level and layer) in its aspect.
    pub fn subresource_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        }
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the owner guarantees the GPU no longer uses the image; the device is
        // alive while `self.ctx` is.
        unsafe {
            if self.view != vk::ImageView::null() {
                device.destroy_image_view(self.view, None);
            }
            device.destroy_image(self.handle, None);
        }
        if let Some(block) = self.block.take() {
            self.ctx.memory().free(block);
        }
    }
}

/// A depth attachment cleared to the far plane whose contents are not kept: what every
/// pass that draws glyphs into its own depth buffer begins with.
pub fn cleared_depth_attachment(view: vk::ImageView) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 0.0,
                stencil: 0,
            },
        })
}
