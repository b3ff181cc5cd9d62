//! The raw Vulkan commands around the core's recording: barriers in, dynamic rendering
//! with the application's attachments, barriers out.
//!
//! wgpu tracks no state for raw commands, so the commands keep to what wgpu believes:
//! they begin with the textures in the layouts wgpu gives its attachment states
//! (`COLOR_TARGET`: COLOR_ATTACHMENT_OPTIMAL, `DEPTH_STENCIL_WRITE`:
//! DEPTH_STENCIL_ATTACHMENT_OPTIMAL), where the encoder before them put the textures, and
//! end with the textures still there. wgpu emits no barrier between two uses in one
//! attachment state (it takes them as ordered), so the commands wait themselves for every
//! earlier command's writes, and make their own writes available to every later command.
use crate::Result;
use glyphcast::ash::vk;

/// Vulkan handles of the application's target for one frame.
pub(crate) struct Attachments {
    /// (image, view) of the colour, depth and resolve textures.
    pub color: (vk::Image, vk::ImageView),
    pub depth: (vk::Image, vk::ImageView),
    pub resolve: Option<(vk::Image, vk::ImageView)>,
    pub depth_format: vk::Format,
    pub extent: vk::Extent2D,
}

const COLOR_LAYOUT: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
const DEPTH_LAYOUT: vk::ImageLayout = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;

/// Whether a depth format has a stencil aspect too.
fn has_stencil(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::D16_UNORM_S8_UINT
            | vk::Format::D24_UNORM_S8_UINT
            | vk::Format::D32_SFLOAT_S8_UINT
    )
}

/// What the glyph pass does to each attachment: (stages, accesses, layout, aspect).
fn uses(
    a: &Attachments,
) -> Vec<(
    vk::Image,
    vk::PipelineStageFlags2,
    vk::AccessFlags2,
    vk::ImageLayout,
    vk::ImageAspectFlags,
)> {
    let color_stage = vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT;
    let color_access =
        vk::AccessFlags2::COLOR_ATTACHMENT_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE;
    let depth_stage = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
    let depth_access = vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE;
    let depth_aspect = if has_stencil(a.depth_format) {
        vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
    } else {
        vk::ImageAspectFlags::DEPTH
    };
    let mut uses = vec![
        (
            a.color.0,
            color_stage,
            color_access,
            COLOR_LAYOUT,
            vk::ImageAspectFlags::COLOR,
        ),
        (
            a.depth.0,
            depth_stage,
            depth_access,
            DEPTH_LAYOUT,
            depth_aspect,
        ),
    ];
    if let Some((image, _)) = a.resolve {
        // A resolve writes in the colour-output stage.
        uses.push((
            image,
            color_stage,
            color_access,
            COLOR_LAYOUT,
            vk::ImageAspectFlags::COLOR,
        ));
    }
    uses
}

/// Every earlier command's writes before the pass (`inward`), or the pass's writes
/// before every later command: layouts unchanged.
fn barriers(a: &Attachments, inward: bool) -> Vec<vk::ImageMemoryBarrier2<'static>> {
    let all = (
        vk::PipelineStageFlags2::ALL_COMMANDS,
        vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE,
    );
    uses(a)
        .into_iter()
        .map(|(image, stage, access, layout, aspect)| {
            let ((src_stage, src_access), (dst_stage, dst_access)) = if inward {
                (all, (stage, access))
            } else {
                ((stage, access), all)
            };
            vk::ImageMemoryBarrier2::default()
                .image(image)
                .subresource_range(
                    vk::ImageSubresourceRange::default()
                        .aspect_mask(aspect)
                        .level_count(1)
                        .layer_count(1),
                )
                .old_layout(layout)
                .new_layout(layout)
                .src_stage_mask(src_stage)
                .src_access_mask(src_access)
                .dst_stage_mask(dst_stage)
                .dst_access_mask(dst_access)
        })
        .collect()
}

/// Records into `cmd` (a recording command buffer of `device`): the inward barriers,
/// dynamic rendering with the attachments loaded and stored (the colour resolved when
/// there is a resolve view), `draw` inside it, and the outward barriers.
pub(crate) fn record_glyph_pass(
    device: &glyphcast::ash::Device,
    cmd: vk::CommandBuffer,
    a: &Attachments,
    draw: impl FnOnce(vk::CommandBuffer) -> Result<()>,
) -> Result<()> {
    let attachment = |view, layout| {
        vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(layout)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)
    };
    let mut color = attachment(a.color.1, COLOR_LAYOUT);
    if let Some((_, view)) = a.resolve {
        color = color
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(view)
            .resolve_image_layout(COLOR_LAYOUT);
    }
    let colors = [color];
    let depth = attachment(a.depth.1, DEPTH_LAYOUT);
    let mut rendering = vk::RenderingInfo::default()
        .render_area(a.extent.into())
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth);
    if has_stencil(a.depth_format) {
        // A depth-stencil view is bound as the stencil attachment too, as the core's
        // pipelines expect (TargetFormats); the glyphs leave the stencil as it is.
        rendering = rendering.stencil_attachment(&depth);
    }
    let inward = barriers(a, true);
    let outward = barriers(a, false);
    // SAFETY: `cmd` is recording outside any rendering; the images and views are the
    // application's, alive until the commands have run (the frame slot holds them).
    unsafe {
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&inward),
        );
        device.cmd_begin_rendering(cmd, &rendering);
    }
    let drawn = draw(cmd);
    // SAFETY: as above; the rendering is ended whatever `draw` recorded.
    unsafe {
        device.cmd_end_rendering(cmd);
        device.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&outward),
        );
    }
    drawn
}
