//! Pieces of frame recording that the headless renderer and the viewer share: image
//! layout transitions, cleared attachments, and copies of a colour image into a buffer
//! that the host then reads.
use ash::vk;

/// A pipeline stage and the accesses in it, one side of a barrier.
pub type Access = (vk::PipelineStageFlags2, vk::AccessFlags2);

/// Nothing to wait for (an image whose old contents are discarded).
pub const NOTHING: Access = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);

/// Colour attachment writes.
pub const COLOR_OUTPUT: Access = (
    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
);

/// Depth tests and writes (reversed depth: cleared, tested, written).
pub const DEPTH_TESTS: Access = (
    vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
    ),
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    ),
);

/// Reads by a copy command.
pub const COPY_READ: Access = (
    vk::PipelineStageFlags2::COPY,
    vk::AccessFlags2::TRANSFER_READ,
);

/// Writes by a copy command.
pub const COPY_WRITE: Access = (
    vk::PipelineStageFlags2::COPY,
    vk::AccessFlags2::TRANSFER_WRITE,
);

/// Writes by any transfer command (copies, fills and updates of buffers).
pub const TRANSFER_WRITES: Access = (
    vk::PipelineStageFlags2::ALL_TRANSFER,
    vk::AccessFlags2::TRANSFER_WRITE,
);

/// Reads by any transfer command.
pub const TRANSFER_READS: Access = (
    vk::PipelineStageFlags2::ALL_TRANSFER,
    vk::AccessFlags2::TRANSFER_READ,
);

/// Storage buffer reads and writes by fragment shaders.
pub const FRAGMENT_STORAGE: Access = (
    vk::PipelineStageFlags2::FRAGMENT_SHADER,
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
            | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
    ),
);

/// A memory barrier from `src` to `dst`.
pub fn memory_barrier(src: Access, dst: Access) -> vk::MemoryBarrier2<'static> {
    vk::MemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)
}

/// A layout transition of `image` (the subresources of `range`) from `old` to `new`,
/// after `src` and before `dst`.
pub fn layout_transition(
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    (old, new): (vk::ImageLayout, vk::ImageLayout),
    src: Access,
    dst: Access,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(range)
        .old_layout(old)
        .new_layout(new)
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)
}

/// A colour attachment of `view` in COLOR_ATTACHMENT_OPTIMAL, cleared to `clear` and
/// stored.
pub fn cleared_color_attachment(
    view: vk::ImageView,
    clear: [f32; 4],
) -> vk::RenderingAttachmentInfo<'static> {
    vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            color: vk::ClearColorValue { float32: clear },
        })
}

/// The copy of a whole single-layer colour image of `extent` into a tightly packed
/// buffer.
pub fn color_image_copy(extent: vk::Extent2D) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(extent.into())
}

/// The copy of the top-left `extent` of a single-layer colour image into another at
/// `offset` (the viewer puts a panel drawn offscreen into its cell of the window).
pub fn color_region_copy(extent: vk::Extent2D, offset: vk::Offset2D) -> vk::ImageCopy {
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    vk::ImageCopy::default()
        .src_subresource(layers)
        .dst_subresource(layers)
        .dst_offset(vk::Offset3D {
            x: offset.x,
            y: offset.y,
            z: 0,
        })
        .extent(extent.into())
}

/// The copy of a tightly packed buffer of `rect.extent` pixels into the region `rect` of
/// a single-layer colour image.
pub fn buffer_to_color_region(rect: vk::Rect2D) -> vk::BufferImageCopy {
    color_image_copy(rect.extent).image_offset(vk::Offset3D {
        x: rect.offset.x,
        y: rect.offset.y,
        z: 0,
    })
}

/// Makes copy writes visible to the host (before it maps and reads the buffer).
pub fn copies_to_host() -> vk::MemoryBarrier2<'static> {
    vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COPY)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)
}

/// Binds a graphics `pipeline` with `set` as its descriptor set 0 and sets the dynamic
/// viewport and scissor: how each pass drawn into the glyphs' depth buffer (glyph boxes,
/// underlay planes, peaks) opens its draws.
///
/// # Safety
/// `cmd` is recording inside dynamic rendering; `pipeline`, `layout` and `set` are alive,
/// and `set` matches set 0 of `layout`.
pub(crate) unsafe fn bind_graphics(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (pipeline, layout): (vk::Pipeline, vk::PipelineLayout),
    set: vk::DescriptorSet,
    (viewport, scissor): (vk::Viewport, vk::Rect2D),
) {
    // SAFETY: the caller's promise.
    unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[scissor]);
        device.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::GRAPHICS,
            layout,
            0,
            &[set],
            &[],
        );
    }
}
