//! The window's frames: swapchain, depth buffer, one command buffer and its sync objects,
//! and the ray-cast pass for the swapchain's format, with no distance attachment (the
//! pass then uses its colour-only fragment shaders). A frame draws the panel at the
//! window's corner in place, with its cell as viewport; the other panels of a montage
//! and the colour bar's strip are drawn offscreen or on the CPU and copied in
//! (`compose`).
//!
//! One frame is in flight: each frame first waits for the previous one, which makes it
//! safe to rewrite the scene's frame block and to read the previous frame's GPU time.
//! Before each frame the swapchain is compared with the window's current size and
//! recreated if it differs or was reported stale (a resize event, OUT_OF_DATE from
//! acquire or present, SUBOPTIMAL), and frames are skipped while the window has no area
//! (minimised), so nothing is rendered into a swapchain known to be stale. An image
//! acquired as SUBOPTIMAL is still drawn and presented (presenting is how it is given
//! back), and the swapchain is recreated before the next frame.
use super::compose::{Composer, PanelDraw, StripDraw, attachment_to_copies};
use crate::error::{Result, VkContext};
use crate::render::RenderSettings;
use crate::render::peaks::PeaksPass;
use crate::render::raycast::{RayCastPass, TargetFormats};
use crate::render::underlay::UnderlayPass;
use crate::vk::recording::{
    Access, COLOR_OUTPUT, COPY_READ, COPY_WRITE, DEPTH_TESTS, NOTHING, cleared_color_attachment,
    color_image_copy, copies_to_host, layout_transition,
};
use crate::vk::{
    Acquired, Buffer, DeviceContext, Gpu, GpuTimer, Image, Surface, Swapchain, color_range,
};
use ash::vk;
use gpu_allocator::MemoryLocation;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// What [`Presenter::render`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Presented {
        extent: vk::Extent2D,
    },
    /// Nothing rendered: the window has no area, or the swapchain had to be recreated.
    Skipped,
}

/// A read-back of the last presented image (`--capture-window`).
pub struct Capture {
    pub width: u32,
    pub height: u32,
    /// RGBA8, sRGB-encoded as on screen.
    pub rgba: Vec<u8>,
}

/// Every member keeps what it was made from alive (the device through its context, a
/// swapchain its surface), so no drop order is needed for soundness; `Drop` waits for
/// the device to be idle before any of them goes.
pub struct Presenter {
    pass: RayCastPass,
    underlay: UnderlayPass,
    peaks: PeaksPass,
    timer: Option<GpuTimer>,
    capture: Option<(Buffer, vk::Extent2D)>,
    composer: Composer,
    depth: Option<Image>,
    swapchain: Option<Swapchain>,
    surface: Surface,
    ctx: DeviceContext,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    acquired: vk::Semaphore,
    in_flight: vk::Fence,
    /// The last submitted frame wrote timestamps.
    timed: bool,
    stale: bool,
    unthrottled: bool,
}

impl Presenter {
    /// # Safety
    /// As [`Surface::new`]: the handles belong to a live window that outlives the
    /// presenter, and `gpu` was made for its display.
    pub unsafe fn new(
        gpu: &Gpu,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        unthrottled: bool,
    ) -> Result<Presenter> {
        // SAFETY: the caller's promise.
        let surface = unsafe { Surface::new(gpu, display, window)? };
        let device = gpu.device();
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create infos; everything is destroyed in Drop. The
        // fence starts signalled: there is no previous frame to wait for.
        let (pool, acquired, in_flight) = unsafe {
            (
                device
                    .create_command_pool(&pool_info, None)
                    .vk("vkCreateCommandPool")?,
                device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                    .vk("vkCreateSemaphore")?,
                device
                    .create_fence(
                        &vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED),
                        None,
                    )
                    .vk("vkCreateFence")?,
            )
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool was just created from this device.
        let cmd =
            unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        // The swapchain's format is only known once it exists; until then the pass has
        // the most likely one and is rebuilt if the swapchain picks another.
        let formats = TargetFormats {
            color: vk::Format::B8G8R8A8_SRGB,
            depth: DEPTH_FORMAT,
            distance: None,
        };
        Ok(Presenter {
            pass: RayCastPass::new(gpu.context(), formats)?,
            underlay: UnderlayPass::new(gpu.context(), formats)?,
            peaks: PeaksPass::new(gpu.context(), formats)?,
            timer: GpuTimer::new(gpu)?,
            capture: None,
            composer: Composer::default(),
            depth: None,
            swapchain: None,
            surface,
            ctx: gpu.context().clone(),
            pool,
            cmd,
            acquired,
            in_flight,
            timed: false,
            stale: true,
            unthrottled,
        })
    }

    /// The underlay's pass, to upload an underlay volume with; rebuilt with the glyph
    /// pass (see [`Presenter::pass_mut`]).
    pub fn underlay_pass(&self) -> &UnderlayPass {
        &self.underlay
    }

    /// The peaks' pass, to upload a panel's peaks with; rebuilt with the glyph pass.
    pub fn peaks_pass(&self) -> &PeaksPass {
        &self.peaks
    }

    /// The pass, to upload scenes with. Its formats may change when the swapchain is
    /// created: [`Presenter::prepare`] says when uploads must be redone.
    pub fn pass_mut(&mut self) -> &mut RayCastPass {
        &mut self.pass
    }

    /// The swapchain no longer fits the window (a resize was reported).
    pub fn mark_stale(&mut self) {
        self.stale = true;
    }

    /// Waits for the previous frame; returns its GPU time if it was timed.
    pub fn wait_previous(&mut self) -> Result<Option<f64>> {
        // SAFETY: the fence belongs to this device.
        unsafe {
            self.ctx
                .device()
                .wait_for_fences(&[self.in_flight], true, u64::MAX)
                .vk("vkWaitForFences")?;
        }
        if std::mem::take(&mut self.timed) {
            return self.timer.as_ref().map(GpuTimer::elapsed_ms).transpose();
        }
        Ok(None)
    }

    /// Makes the swapchain match a window of `size`: recreates it if stale or of another
    /// size. Returns None while the window has no area, else whether the pass was rebuilt
    /// for a new colour format (scenes uploaded with the old pass must be uploaded again).
    pub fn prepare(&mut self, gpu: &Gpu, size: vk::Extent2D) -> Result<Option<bool>> {
        if size.width == 0 || size.height == 0 {
            return Ok(None);
        }
        let fits = self
            .swapchain
            .as_ref()
            .is_some_and(|s| s.extent == size && !self.stale);
        if fits {
            return Ok(Some(false));
        }
        gpu.wait_idle()?;
        let old = self.swapchain.take();
        self.depth = None;
        let Some(swapchain) =
            Swapchain::new(gpu, &self.surface, size, self.unthrottled, old.as_ref())?
        else {
            return Ok(None);
        };
        drop(old);
        self.depth = Some(Image::new(
            gpu.context(),
            "window depth",
            swapchain.extent,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?);
        let mut rebuilt = false;
        if swapchain.format != self.pass.formats().color {
            let formats = TargetFormats {
                color: swapchain.format,
                ..self.pass.formats()
            };
            self.pass = RayCastPass::new(gpu.context(), formats)?;
            self.underlay = UnderlayPass::new(gpu.context(), formats)?;
            self.peaks = PeaksPass::new(gpu.context(), formats)?;
            self.composer.reset();
            rebuilt = true;
        }
        if !matches!(
            swapchain.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
        ) {
            eprintln!(
                "warning: the window has no sRGB format ({:?}); colours will look darker",
                swapchain.format
            );
        }
        self.swapchain = Some(swapchain);
        self.stale = false;
        Ok(Some(rebuilt))
    }

    /// The swapchain's extent, once [`Presenter::prepare`] made one.
    pub fn extent(&self) -> Option<vk::Extent2D> {
        self.swapchain.as_ref().map(|s| s.extent)
    }

    /// Renders and presents one frame (after [`Presenter::prepare`] and
    /// [`Presenter::wait_previous`]): the `panels`, each in its cell (uploaded with
    /// [`Presenter::pass_mut`], underlays with [`Presenter::underlay_pass`]), and the
    /// colour bar's `strip`; the rest of the window is background. `capture` also copies
    /// the image for [`Presenter::capture`].
    pub fn render(
        &mut self,
        gpu: &Gpu,
        panels: &mut [PanelDraw],
        strip: Option<StripDraw>,
        settings: &RenderSettings,
        capture: bool,
    ) -> Result<Outcome> {
        let Some(swapchain) = self.swapchain.as_ref() else {
            return Ok(Outcome::Skipped);
        };
        let extent = swapchain.extent;
        let copies = strip.is_some() || panels.iter().any(|p| !p.in_place());
        if copies && !swapchain.writable {
            return Err(crate::Error::Setup(
                "this window's swapchain images cannot be copied into (no TRANSFER_DST \
                 usage): the viewer cannot show a montage or a colour bar here"
                    .into(),
            ));
        }
        let format = swapchain.format;
        let index = match swapchain.acquire(self.acquired)? {
            Acquired::OutOfDate => {
                self.stale = true;
                return Ok(Outcome::Skipped);
            }
            Acquired::Image { index, suboptimal } => {
                self.stale |= suboptimal;
                index
            }
        };
        // The previous frame is done (wait_previous), so the frame blocks, the offscreen
        // target and the strip's buffer are free.
        for panel in panels.iter_mut() {
            panel.scene.set_frame(&panel.frame)?;
            if let Some(peaks) = panel.peaks.as_mut() {
                peaks.set_frame(&panel.frame)?;
            }
        }
        // The pipelines of this frame's method (a key may have just switched it), made
        // before recording: the pass never compiles while it records.
        for panel in panels.iter() {
            for set in &panel.scene.sets {
                let method = crate::render::raycast::batch_method(set.shape, settings.method);
                self.pass.prepare(set.layout, method)?;
            }
        }
        let largest = panels
            .iter()
            .filter(|p| !p.in_place())
            .map(|p| p.cell.extent)
            .reduce(|a, b| vk::Extent2D {
                width: a.width.max(b.width),
                height: a.height.max(b.height),
            });
        if let Some(target) = largest {
            self.composer
                .ensure_target(gpu.context(), format, DEPTH_FORMAT, target)?;
        }
        if let Some(strip) = &strip {
            let bgra = matches!(
                format,
                vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
            );
            self.composer.stage_strip(gpu.context(), strip.rgba, bgra)?;
        }
        if capture {
            self.ensure_capture_buffer(gpu, extent)?;
        }
        // SAFETY: the fence is signalled and about to be reused by this submission.
        unsafe { self.ctx.device().reset_fences(&[self.in_flight]) }.vk("vkResetFences")?;
        let strip = strip.map(|s| s.rect);
        self.record(index, panels, strip, settings, capture)?;
        let Some(swapchain) = self.swapchain.as_ref() else {
            return Ok(Outcome::Skipped);
        };
        let wait = [vk::SemaphoreSubmitInfo::default()
            .semaphore(self.acquired)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let signal = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.render_finished[index as usize])
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signal)];
        // SAFETY: the command buffer is recorded; the semaphores and fence are ours.
        unsafe {
            self.ctx
                .device()
                .queue_submit2(gpu.queue, &submit, self.in_flight)
        }
        .vk("vkQueueSubmit2")?;
        self.timed = self.timer.is_some();
        if !swapchain.present(gpu.queue, index)? {
            self.stale = true;
        }
        Ok(Outcome::Presented { extent })
    }

    fn ensure_capture_buffer(&mut self, gpu: &Gpu, extent: vk::Extent2D) -> Result<()> {
        if self.capture.as_ref().is_some_and(|(_, e)| *e == extent) {
            return Ok(());
        }
        let readable = self.swapchain.as_ref().is_some_and(|s| s.readable);
        if !readable {
            return Err(crate::Error::Setup(
                "this window's swapchain images cannot be read back (no TRANSFER_SRC usage)".into(),
            ));
        }
        let bytes = 4 * u64::from(extent.width) * u64::from(extent.height);
        let buffer = Buffer::new(
            gpu.context(),
            "window capture",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.capture = Some((buffer, extent));
        Ok(())
    }

    /// The image of the last frame rendered with `capture`, once it completed
    /// (after [`Presenter::wait_previous`]), as RGBA.
    pub fn capture(&self) -> Result<Option<Capture>> {
        let (Some((buffer, extent)), Some(swapchain)) = (&self.capture, &self.swapchain) else {
            return Ok(None);
        };
        let mut rgba = buffer.read()?.to_vec();
        if matches!(
            swapchain.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        ) {
            for pixel in rgba.chunks_exact_mut(4) {
                pixel.swap(0, 2);
            }
        }
        Ok(Some(Capture {
            width: extent.width,
            height: extent.height,
            rgba,
        }))
    }

    fn record(
        &mut self,
        index: u32,
        panels: &[PanelDraw],
        strip: Option<vk::Rect2D>,
        settings: &RenderSettings,
        capture: bool,
    ) -> Result<()> {
        let (Some(swapchain), Some(depth)) = (self.swapchain.as_ref(), self.depth.as_ref()) else {
            return Ok(());
        };
        let (d, cmd) = (self.ctx.device(), self.cmd);
        let image = swapchain.images[index as usize];
        let extent = swapchain.extent;
        let color_out = COLOR_OUTPUT;
        let to_attachment = [
            // The acquire semaphore is waited on at COLOR_ATTACHMENT_OUTPUT; the layout
            // change waits there too.
            layout_transition(
                image,
                color_range(),
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                ),
                (color_out.0, vk::AccessFlags2::NONE),
                color_out,
            ),
            // The previous frame's depth writes are done before this frame clears.
            layout_transition(
                depth.handle,
                depth.subresource_range(),
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                ),
                (
                    DEPTH_TESTS.0,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                ),
                DEPTH_TESTS,
            ),
        ];
        let bg = settings.background;
        let background = [bg[0], bg[1], bg[2], 1.0];
        let color_attachment = [cleared_color_attachment(
            swapchain.views[index as usize],
            background,
        )];
        let depth_attachment = crate::vk::cleared_depth_attachment(depth.view);
        let rendering = vk::RenderingInfo::default()
            .render_area(extent.into())
            .layer_count(1)
            .color_attachments(&color_attachment)
            .depth_attachment(&depth_attachment);
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the previous submission of `cmd` completed (wait_previous); every
        // handle recorded lives until this frame completes.
        unsafe {
            d.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            d.begin_command_buffer(cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_attachment),
            );
        }
        if let Some(timer) = &self.timer {
            timer.start(cmd);
        }
        // SAFETY: as above.
        unsafe { d.cmd_begin_rendering(cmd, &rendering) };
        // The panel at the corner: its viewport is its cell.
        for panel in panels.iter().filter(|p| p.in_place()) {
            let passes = (&mut self.pass, &self.underlay, &self.peaks);
            record_panel(passes, cmd, panel, settings)?;
        }
        // SAFETY: as above.
        unsafe { d.cmd_end_rendering(cmd) };
        let copied: Vec<&PanelDraw> = panels.iter().filter(|p| !p.in_place()).collect();
        let last = if copied.is_empty() && strip.is_none() {
            (vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, COLOR_OUTPUT)
        } else {
            let to_copies = [attachment_to_copies(image)];
            // SAFETY: as above.
            unsafe {
                d.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().image_memory_barriers(&to_copies),
                );
            }
            for panel in copied {
                let passes = (&mut self.pass, &self.underlay, &self.peaks);
                self.composer
                    .record_panel(d, cmd, image, panel.cell, background, || {
                        record_panel(passes, cmd, panel, settings)
                    })?;
            }
            if let Some(rect) = strip {
                self.composer.record_strip(d, cmd, image, rect)?;
            }
            (vk::ImageLayout::TRANSFER_DST_OPTIMAL, COPY_WRITE)
        };
        if let Some(timer) = &self.timer {
            timer.stop(cmd);
        }
        let readback = self
            .capture
            .as_ref()
            .filter(|_| capture)
            .map(|(b, _)| b.handle);
        record_present_transition(d, cmd, image, extent, last, readback);
        // SAFETY: recording began above.
        unsafe { d.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        Ok(())
    }
}

/// Records `panel`'s underlay, glyphs and peaks, drawn into an attachment whose corner
/// is the panel's (rendering has begun).
fn record_panel(
    (pass, underlay, peaks): (&mut RayCastPass, &UnderlayPass, &PeaksPass),
    cmd: vk::CommandBuffer,
    panel: &PanelDraw,
    settings: &RenderSettings,
) -> Result<()> {
    let extent = panel.cell.extent;
    if let Some((volume, planes)) = panel.underlay {
        underlay.record(cmd, volume, planes, panel.frame.view_proj, extent);
    }
    pass.record(cmd, panel.scene, extent, settings.method)?;
    if let Some(on_gpu) = panel.peaks.as_deref() {
        peaks.record(cmd, on_gpu, extent);
    }
    Ok(())
}

/// The image from its `last` layout (after the accesses there) to PRESENT_SRC, through a
/// copy into `readback` when given.
fn record_present_transition(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    (last_layout, last_access): (vk::ImageLayout, Access),
    readback: Option<vk::Buffer>,
) {
    let from_attachment = |new, dst| {
        let layouts = (last_layout, new);
        layout_transition(image, color_range(), layouts, last_access, dst)
    };
    let Some(buffer) = readback else {
        // Presentation waits on the semaphore; no destination stage is needed.
        let to_present = [from_attachment(vk::ImageLayout::PRESENT_SRC_KHR, NOTHING)];
        // SAFETY: `cmd` is recording outside rendering; the image is the acquired one.
        unsafe {
            d.cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().image_memory_barriers(&to_present),
            );
        }
        return;
    };
    let to_transfer = [from_attachment(
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        COPY_READ,
    )];
    let to_present = [layout_transition(
        image,
        color_range(),
        (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::ImageLayout::PRESENT_SRC_KHR,
        ),
        (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::NONE),
        NOTHING,
    )];
    let host_read = [copies_to_host()];
    let copy = color_image_copy(extent);
    // SAFETY: as above; the buffer holds width * height * 4 bytes.
    unsafe {
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_transfer),
        );
        d.cmd_copy_image_to_buffer(
            cmd,
            image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer,
            &[copy],
        );
        d.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default()
                .image_memory_barriers(&to_present)
                .memory_barriers(&host_read),
        );
    }
}

impl Drop for Presenter {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: waiting for the device leaves nothing in flight that uses these (nor the
        // members dropped after this body); the device is alive while `self.ctx` is.
        unsafe {
            let _ = device.device_wait_idle();
            device.destroy_fence(self.in_flight, None);
            device.destroy_semaphore(self.acquired, None);
            device.destroy_command_pool(self.pool, None);
        }
    }
}
