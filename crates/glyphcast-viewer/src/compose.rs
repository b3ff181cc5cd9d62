//! What the window shows besides the panel drawn straight into the swapchain image: the
//! other panels of a montage, the colour bar's strip and a lightbox's captions, copied
//! into their places.
//!
//! The ray-cast shaders find each pixel's ray from `gl_FragCoord`, which counts from the
//! attachment's corner, not the viewport's, so a panel drawn into its cell through an
//! offset viewport would cast the wrong rays. The panel at the window's corner is drawn
//! in place (its viewport is its cell); every other panel is drawn, as the headless
//! renderer draws it, at the corner of an offscreen target of the swapchain's format, and
//! copied into its cell. One target serves all panels in turn (they share a cell size).
//! The strip and the captions are drawn on the CPU (`render::compose::colorbar`, the
//! pixels `render --colorbar` appends; `render::compose::labels::caption_patch`, the
//! opaque box `render --lightbox` draws) and copied in from a host-visible buffer, byte
//! for byte.
use ash::vk;
use glyphcast::error::{Error, Result};
use glyphcast::render::component::UploadedGlyphs;
use glyphcast::render::frame::FrameParams;
use glyphcast::render::peaks::PeaksGpu;
use glyphcast::render::underlay::{UnderlayGpu, UnderlayPlane};
use glyphcast::vk::recording::{
    Access, COLOR_OUTPUT, COPY_READ, COPY_WRITE, DEPTH_TESTS, buffer_to_color_region,
    cleared_color_attachment, color_region_copy, layout_transition,
};
use glyphcast::vk::{Buffer, DeviceContext, Image, cleared_depth_attachment, color_range};
use gpu_allocator::MemoryLocation;

/// One panel of a frame: its glyphs (and underlay), its frame block and its cell of the
/// window. The peaks are the frame slot's own copy (a peak set has one frame block).
pub struct PanelDraw<'a> {
    pub glyphs: &'a mut UploadedGlyphs,
    pub underlay: Option<(&'a UnderlayGpu, &'a [UnderlayPlane])>,
    /// Its fibre peaks, if any.
    pub peaks: Option<&'a mut PeaksGpu>,
    /// The frame block for the cell's size.
    pub frame: FrameParams,
    /// Where the panel goes in the window.
    pub cell: vk::Rect2D,
}

impl PanelDraw<'_> {
    /// Whether the panel starts at the window's corner, where it is drawn in place.
    pub fn in_place(&self) -> bool {
        self.cell.offset == vk::Offset2D::default()
    }
}

/// Pixels copied into the window for a frame (the colour bar's strip, a caption): RGBA
/// (sRGB-encoded, as the PNG stores them), `rect.extent` of them, and where they go.
pub struct PatchDraw<'a> {
    pub rgba: &'a [u8],
    pub rect: vk::Rect2D,
}

/// The offscreen target of the panels that are copied, and the patches' staging buffer:
/// one per frame in flight (`slots`), since a frame writes both.
#[derive(Default)]
pub struct Composer {
    target: Option<(Image, Image)>,
    patches: Option<Buffer>,
    /// Where each staged patch goes, and its first byte in the buffer.
    staged: Vec<(vk::Rect2D, u64)>,
}

impl Composer {
    /// Forgets the target (the swapchain's format may have changed).
    pub fn reset(&mut self) {
        self.target = None;
    }

    /// Makes the offscreen target (colour of `format`, and depth of `depth_format`) at
    /// least `extent` large.
    pub fn ensure_target(
        &mut self,
        ctx: &DeviceContext,
        format: vk::Format,
        depth_format: vk::Format,
        extent: vk::Extent2D,
    ) -> Result<()> {
        let fits = self.target.as_ref().is_some_and(|(color, _)| {
            color.format == format
                && color.extent.width >= extent.width
                && color.extent.height >= extent.height
        });
        if fits {
            return Ok(());
        }
        self.target = None;
        let color = Image::new(
            ctx,
            "window panel",
            extent,
            format,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
        )?;
        let depth = Image::new(
            ctx,
            "window panel depth",
            extent,
            depth_format,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        self.target = Some((color, depth));
        Ok(())
    }

    /// Puts the patches' pixels into the staging buffer, one after another, in the
    /// swapchain's byte order (`bgra`: blue first). The slot's previous frame has
    /// completed, so the buffer is free.
    pub fn stage_patches(
        &mut self,
        ctx: &DeviceContext,
        patches: &[PatchDraw],
        bgra: bool,
    ) -> Result<()> {
        self.staged.clear();
        let mut bytes = Vec::with_capacity(patches.iter().map(|p| p.rgba.len()).sum());
        for patch in patches {
            self.staged.push((patch.rect, bytes.len() as u64));
            if bgra {
                bytes.extend(
                    patch
                        .rgba
                        .chunks_exact(4)
                        .flat_map(|p| [p[2], p[1], p[0], p[3]]),
                );
            } else {
                bytes.extend_from_slice(patch.rgba);
            }
        }
        let size = bytes.len() as u64;
        if self.patches.as_ref().is_none_or(|b| b.size < size) {
            self.patches = None;
            self.patches = Some(Buffer::new(
                ctx,
                "window patches",
                size.max(4),
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::CpuToGpu,
            )?);
        }
        match self.patches.as_mut() {
            Some(buffer) if !bytes.is_empty() => buffer.write(&bytes),
            _ => Ok(()),
        }
    }

    /// Records one copied panel: drawn into the target by `draw` (between the begin and
    /// end of rendering, with the cell's size), then copied into `image` (in
    /// TRANSFER_DST_OPTIMAL) at the cell. `background` clears the target.
    pub fn record_panel(
        &self,
        d: &ash::Device,
        cmd: vk::CommandBuffer,
        image: vk::Image,
        cell: vk::Rect2D,
        background: [f32; 4],
        draw: impl FnOnce() -> Result<()>,
    ) -> Result<()> {
        let Some((color, depth)) = self.target.as_ref() else {
            return Err(Error::Call {
                call: "record_panel",
                expected: "an offscreen target for a window panel",
            });
        };
        let to_attachment = [
            // After the previous panel's copy read the target.
            layout_transition(
                color.handle,
                color_range(),
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
                (COPY_READ.0, vk::AccessFlags2::NONE),
                COLOR_OUTPUT,
            ),
            layout_transition(
                depth.handle,
                depth.subresource_range(),
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                ),
                DEPTH_TESTS,
                DEPTH_TESTS,
            ),
        ];
        let to_source = [layout_transition(
            color.handle,
            color_range(),
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            ),
            COLOR_OUTPUT,
            COPY_READ,
        )];
        let color_attachment = [cleared_color_attachment(color.view, background)];
        let depth_attachment = cleared_depth_attachment(depth.view);
        let rendering = vk::RenderingInfo::default()
            .render_area(cell.extent.into())
            .layer_count(1)
            .color_attachments(&color_attachment)
            .depth_attachment(&depth_attachment);
        // SAFETY: `cmd` is recording outside rendering; the target and `image` live until
        // the frame completes (the presenter waits for its slot before reusing or dropping
        // either).
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
            );
            d.cmd_begin_rendering(cmd, &rendering);
        }
        draw()?;
        // SAFETY: as above; the copy lies inside both images (the target is at least the
        // cell's size, the cell inside the window).
        unsafe {
            d.cmd_end_rendering(cmd);
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_source),
            );
            d.cmd_copy_image(
                cmd,
                color.handle,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[color_region_copy(cell.extent, cell.offset)],
            );
        }
        Ok(())
    }

    /// Records the copies of the staged patches into `image` (in TRANSFER_DST_OPTIMAL).
    pub fn record_patches(
        &self,
        d: &ash::Device,
        cmd: vk::CommandBuffer,
        image: vk::Image,
    ) -> Result<()> {
        if self.staged.is_empty() {
            return Ok(());
        }
        let Some(buffer) = self.patches.as_ref() else {
            return Err(Error::Call {
                call: "record_patches",
                expected: "stage_patches first",
            });
        };
        let regions: Vec<vk::BufferImageCopy> = self
            .staged
            .iter()
            .map(|(rect, offset)| buffer_to_color_region(*rect).buffer_offset(*offset))
            .collect();
        // SAFETY: the buffer holds each rect's pixels at its offset (stage_patches),
        // written by the host before the submission (which makes them visible); the
        // rects lie inside the image.
        unsafe {
            d.cmd_copy_buffer_to_image(
                cmd,
                buffer.handle,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
            );
        }
        Ok(())
    }
}

/// The barrier that hands the swapchain image from the in-place draw (colour attachment
/// writes) to the copies.
pub fn attachment_to_copies(image: vk::Image) -> vk::ImageMemoryBarrier2<'static> {
    into_copies(
        image,
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        COLOR_OUTPUT,
    )
}

/// The barrier between the copied panels and the patches copied over them (both
/// transfer writes to the swapchain image).
pub fn copies_to_patches(image: vk::Image) -> vk::ImageMemoryBarrier2<'static> {
    into_copies(image, vk::ImageLayout::TRANSFER_DST_OPTIMAL, COPY_WRITE)
}

/// The swapchain image from `layout`, written by `access`, to the copies' writes.
fn into_copies(
    image: vk::Image,
    layout: vk::ImageLayout,
    access: Access,
) -> vk::ImageMemoryBarrier2<'static> {
    layout_transition(
        image,
        color_range(),
        (layout, vk::ImageLayout::TRANSFER_DST_OPTIMAL),
        access,
        COPY_WRITE,
    )
}
