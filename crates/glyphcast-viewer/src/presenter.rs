//! The window's frames: swapchain, the frames in flight ([`FrameSlot`]: command buffer,
//! fence, semaphore, depth buffer, offscreen target, patch buffer, timer, capture buffer
//! each), and the passes for the swapchain's format with no distance attachment (the
//! glyph pass then uses its colour-only fragment shaders). The glyphs are drawn through
//! the engine component, [`GlyphRenderer`], made for the viewer's frames in flight, as an
//! engine draws them: each frame writes its slot's frame block of the shared
//! [`UploadedGlyphs`] and records them with [`GlyphRenderer::record_glyphs`]. A frame
//! draws the panel at the window's corner in place, with its cell as viewport; the other
//! panels of a montage and the colour bar's strip are drawn offscreen or on the CPU and
//! copied in (`compose`).
//!
//! Frames in flight: a frame first waits for its slot's fence (the frame recorded
//! `frames_in_flight` frames earlier), never for the device, so the previous frame may
//! still be on the GPU while this one is recorded. That wait makes the slot's frame
//! blocks, offscreen target, patch buffer and timer free, and gives that earlier frame's
//! GPU time. Before each frame the swapchain is compared with the window's current size
//! and recreated if it differs or was reported stale (a resize event, OUT_OF_DATE from
//! acquire or present, SUBOPTIMAL), after waiting for the device (a resize, not a frame);
//! frames are skipped while the window has no area (minimised), so nothing is rendered
//! into a swapchain known to be stale. An image acquired as SUBOPTIMAL is still drawn and
//! presented (presenting is how it is given back), and the swapchain is recreated before
//! the next frame.
use super::compose::{PanelDraw, PatchDraw, attachment_to_copies, copies_to_patches};
use super::slots::FrameSlot;
use ash::vk;
use glyphcast::error::{Result, VkContext};
use glyphcast::render::RenderSettings;
use glyphcast::render::component::{GlyphRenderer, RendererDesc};
use glyphcast::render::peaks::PeaksPass;
use glyphcast::render::raycast::{FrameTarget, PassOptions, TargetFormats};
use glyphcast::render::underlay::UnderlayPass;
use glyphcast::render::underlay_shadows::UnderlayShadowPass;
use glyphcast::vk::recording::{
    Access, COLOR_OUTPUT, COPY_READ, COPY_WRITE, DEPTH_TESTS, NOTHING, cleared_color_attachment,
    color_image_copy, copies_to_host, layout_transition,
};
use glyphcast::vk::{Acquired, DeviceContext, Gpu, Surface, Swapchain, color_range};
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
    glyphs: GlyphRenderer,
    underlay: UnderlayPass,
    /// The underlay receiving the glyphs' shadows (its pipelines made as glyphs that
    /// cast them come).
    underlay_shadows: UnderlayShadowPass,
    peaks: PeaksPass,
    slots: Vec<FrameSlot>,
    /// The slot the next frame records into.
    next: usize,
    /// The slot of the last submitted frame.
    last: Option<usize>,
    swapchain: Option<Swapchain>,
    surface: Surface,
    ctx: DeviceContext,
    /// The queue every frame is submitted to and presented from.
    queue: vk::Queue,
    pool: vk::CommandPool,
    stale: bool,
    unthrottled: bool,
}

impl Presenter {
    /// A presenter with `frames_in_flight` frame slots, its glyph renderer drawing with
    /// `settings`' method at first.
    ///
    /// # Safety
    /// As [`Surface::new`]: the handles belong to a live window that outlives the
    /// presenter, and `gpu` was made for its display.
    pub unsafe fn new(
        gpu: &Gpu,
        (display, window): (RawDisplayHandle, RawWindowHandle),
        unthrottled: bool,
        frames_in_flight: usize,
        settings: &RenderSettings,
    ) -> Result<Presenter> {
        // SAFETY: the caller's promise.
        let surface = unsafe { Surface::new(gpu, display, window)? };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info; destroyed in Drop.
        let pool = unsafe { gpu.device().create_command_pool(&pool_info, None) }
            .vk("vkCreateCommandPool")?;
        let slots = (0..frames_in_flight.max(1))
            .map(|_| FrameSlot::new(gpu, pool))
            .collect::<Result<Vec<_>>>();
        let slots = match slots {
            Ok(slots) => slots,
            Err(e) => {
                // SAFETY: nothing allocated from the pool is in use.
                unsafe { gpu.device().destroy_command_pool(pool, None) };
                return Err(e);
            }
        };
        // The swapchain's format is only known once it exists; until then the passes
        // have the most likely one and are rebuilt if the swapchain picks another.
        let formats = TargetFormats {
            color: vk::Format::B8G8R8A8_SRGB,
            depth: DEPTH_FORMAT,
            distance: None,
        };
        let desc = renderer_desc(formats, slots.len(), settings);
        Ok(Presenter {
            glyphs: GlyphRenderer::new(gpu.context(), &desc)?,
            underlay: UnderlayPass::new(gpu.context(), formats)?,
            underlay_shadows: UnderlayShadowPass::new(gpu.context(), formats)?,
            peaks: PeaksPass::new(gpu.context(), formats)?,
            slots,
            next: 0,
            last: None,
            swapchain: None,
            surface,
            ctx: gpu.context().clone(),
            queue: gpu.queue,
            pool,
            stale: true,
            unthrottled,
        })
    }

    /// The underlay's pass, to upload an underlay volume with; rebuilt with the glyph
    /// renderer (see [`Presenter::glyphs_mut`]).
    pub fn underlay_pass(&self) -> &UnderlayPass {
        &self.underlay
    }

    /// The peaks' pass, to upload a panel's peaks with; rebuilt with the glyph renderer.
    pub fn peaks_pass(&self) -> &PeaksPass {
        &self.peaks
    }

    /// The glyph renderer, to upload glyphs with and retire replaced ones. Its formats
    /// may change when the swapchain is created: [`Presenter::prepare`] says when
    /// uploads must be redone.
    pub fn glyphs_mut(&mut self) -> &mut GlyphRenderer {
        &mut self.glyphs
    }

    /// The glyph renderer (its retired uploads, its pass).
    pub fn glyphs(&self) -> &GlyphRenderer {
        &self.glyphs
    }

    /// How many frames may be in flight.
    pub fn frames_in_flight(&self) -> usize {
        self.slots.len()
    }

    /// The swapchain no longer fits the window (a resize was reported).
    pub fn mark_stale(&mut self) {
        self.stale = true;
    }

    /// Begins the next frame: waits for its slot's previous frame (not for the others)
    /// and tells the glyph renderer, which drops retired glyphs no slot can still read.
    /// Returns the slot and the GPU time of that previous frame, if it was timed.
    pub fn begin_frame(&mut self) -> Result<(usize, Option<f64>)> {
        let slot = self.next;
        let gpu_ms = self.slots[slot].wait()?;
        self.glyphs.begin_frame(slot)?;
        Ok((slot, gpu_ms))
    }

    /// Whether a frame other than `slot`'s is still on the GPU.
    pub fn others_in_flight(&self, slot: usize) -> Result<bool> {
        for (k, other) in self.slots.iter().enumerate() {
            if k != slot && other.in_flight()? {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Makes the swapchain match a window of `size`: recreates it if stale or of another
    /// size. Returns None while the window has no area, else whether the passes were
    /// rebuilt for a new colour format (glyphs uploaded with the old renderer must be
    /// uploaded again).
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
        // A new swapchain (a resize), not a frame: every slot's images are replaced.
        gpu.wait_idle()?;
        let old = self.swapchain.take();
        for slot in &mut self.slots {
            slot.depth = None;
        }
        let Some(swapchain) =
            Swapchain::new(gpu, &self.surface, size, self.unthrottled, old.as_ref())?
        else {
            return Ok(None);
        };
        drop(old);
        for slot in &mut self.slots {
            slot.make_depth(DEPTH_FORMAT, swapchain.extent)?;
        }
        let mut rebuilt = false;
        if swapchain.format != self.glyphs.pass().formats().color {
            let formats = TargetFormats {
                color: swapchain.format,
                ..self.glyphs.pass().formats()
            };
            let desc = renderer_desc(formats, self.slots.len(), &RenderSettings::default());
            self.glyphs = GlyphRenderer::new(gpu.context(), &desc)?;
            self.underlay = UnderlayPass::new(gpu.context(), formats)?;
            self.underlay_shadows = UnderlayShadowPass::new(gpu.context(), formats)?;
            self.peaks = PeaksPass::new(gpu.context(), formats)?;
            for slot in &mut self.slots {
                slot.composer.reset();
            }
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

    /// Renders and presents one frame in `slot` (after [`Presenter::prepare`] and
    /// [`Presenter::begin_frame`], which gave the slot): the `panels`, each in its cell
    /// (glyphs uploaded with [`Presenter::glyphs_mut`], underlays with
    /// [`Presenter::underlay_pass`], peaks this slot's own), and the `patches` (the
    /// colour bar's strip, a lightbox's captions) on top; the rest of the window is
    /// background. `capture` also copies the image for
    /// [`Presenter::capture`]. Does not wait for the frame.
    pub fn render(
        &mut self,
        slot: usize,
        panels: &mut [PanelDraw],
        patches: &[PatchDraw],
        settings: &RenderSettings,
        capture: bool,
    ) -> Result<Outcome> {
        let Some(swapchain) = self.swapchain.as_ref() else {
            return Ok(Outcome::Skipped);
        };
        let extent = swapchain.extent;
        let copies = !patches.is_empty() || panels.iter().any(|p| !p.in_place());
        if copies && !swapchain.writable {
            return Err(glyphcast::Error::Setup {
                missing: "TRANSFER_DST usage of this window's swapchain images, which a \
                          montage or a colour bar in the viewer needs",
                found: None,
            });
        }
        if capture && !swapchain.readable {
            return Err(glyphcast::Error::Setup {
                missing: "TRANSFER_SRC usage of this window's swapchain images, which a \
                          capture needs",
                found: None,
            });
        }
        let format = swapchain.format;
        let index = match swapchain.acquire(self.slots[slot].acquired)? {
            Acquired::OutOfDate => {
                self.stale = true;
                return Ok(Outcome::Skipped);
            }
            Acquired::Image { index, suboptimal } => {
                self.stale |= suboptimal;
                index
            }
        };
        // The slot's previous frame is done (begin_frame), so its frame blocks, offscreen
        // target and patch buffer are free; the other slots' frames read their own.
        for panel in panels.iter_mut() {
            let target = FrameTarget {
                frame_index: slot,
                ..FrameTarget::whole(panel.cell.extent)
            };
            panel.glyphs.set_frame(&panel.frame, &target)?;
            if let Some(peaks) = panel.peaks.as_mut() {
                peaks.set_frame(&panel.frame)?;
            }
            if panel.underlay.is_some() {
                self.underlay_shadows.prepare(panel.glyphs)?;
            }
        }
        self.stage(slot, panels, patches, (format, extent), capture)?;
        self.record(slot, index, panels, !patches.is_empty(), settings, capture)?;
        self.submit_and_present(slot, index)?;
        Ok(Outcome::Presented { extent })
    }

    /// Makes `slot`'s offscreen target fit the copied panels, stages the patches' pixels
    /// and makes the capture buffer, for a swapchain of `format` and `extent`.
    fn stage(
        &mut self,
        slot: usize,
        panels: &[PanelDraw],
        patches: &[PatchDraw],
        (format, extent): (vk::Format, vk::Extent2D),
        capture: bool,
    ) -> Result<()> {
        let frame = &mut self.slots[slot];
        let largest = panels
            .iter()
            .filter(|p| !p.in_place())
            .map(|p| p.cell.extent)
            .reduce(|a, b| vk::Extent2D {
                width: a.width.max(b.width),
                height: a.height.max(b.height),
            });
        if let Some(target) = largest {
            frame
                .composer
                .ensure_target(&self.ctx, format, DEPTH_FORMAT, target)?;
        }
        let bgra = matches!(
            format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        );
        frame.composer.stage_patches(&self.ctx, patches, bgra)?;
        if capture {
            frame.ensure_capture(extent)?;
        }
        Ok(())
    }

    /// Submits `slot`'s recorded frame (waiting for its image to be acquired, signalling
    /// the image's render-finished semaphore and the slot's fence) and presents image
    /// `index`; the next frame goes to the next slot.
    fn submit_and_present(&mut self, slot: usize, index: u32) -> Result<()> {
        let (Some(swapchain), frame) = (self.swapchain.as_ref(), &mut self.slots[slot]) else {
            return Ok(());
        };
        let wait = [vk::SemaphoreSubmitInfo::default()
            .semaphore(frame.acquired)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let signal = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.render_finished[index as usize])
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(frame.cmd)];
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signal)];
        let device = self.ctx.device();
        // SAFETY: the fence is signalled (begin_frame waited for it) and reused by this
        // submission; the command buffer is recorded; the semaphores are ours.
        unsafe {
            device.reset_fences(&[frame.done]).vk("vkResetFences")?;
            device
                .queue_submit2(self.queue, &submit, frame.done)
                .vk("vkQueueSubmit2")?;
        }
        frame.timed = frame.timer.is_some();
        self.last = Some(slot);
        self.next = (slot + 1) % self.slots.len();
        if !swapchain.present(self.queue, index)? {
            self.stale = true;
        }
        Ok(())
    }

    /// Waits for every frame in flight (the end of a scripted run, before reading its
    /// capture).
    pub fn wait_all(&mut self) -> Result<()> {
        for slot in &mut self.slots {
            slot.wait()?;
        }
        Ok(())
    }

    /// The image of the last frame rendered with `capture`, once every frame completed
    /// (after [`Presenter::wait_all`]), as RGBA.
    pub fn capture(&self) -> Result<Option<Capture>> {
        let slot = self.last.and_then(|k| self.slots.get(k));
        let (Some((buffer, extent)), Some(swapchain)) =
            (slot.and_then(|s| s.capture.as_ref()), &self.swapchain)
        else {
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
        &self,
        slot: usize,
        index: u32,
        panels: &[PanelDraw],
        patched: bool,
        settings: &RenderSettings,
        capture: bool,
    ) -> Result<()> {
        let frame = &self.slots[slot];
        let (Some(swapchain), Some(depth)) = (self.swapchain.as_ref(), frame.depth.as_ref()) else {
            return Ok(());
        };
        let (d, cmd) = (self.ctx.device(), frame.cmd);
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
            // The slot's previous frame's depth writes are done before this frame clears.
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
        let depth_attachment = glyphcast::vk::cleared_depth_attachment(depth.view);
        let rendering = vk::RenderingInfo::default()
            .render_area(extent.into())
            .layer_count(1)
            .color_attachments(&color_attachment)
            .depth_attachment(&depth_attachment);
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the slot's previous submission of `cmd` completed (begin_frame); every
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
        if let Some(timer) = &frame.timer {
            timer.start(cmd);
        }
        let passes = (
            &self.glyphs,
            (&self.underlay, &self.underlay_shadows),
            &self.peaks,
        );
        // The compute ray caster's dispatches, outside any rendering (nothing for panels
        // drawn on the fragment path): each panel's own buffers.
        for panel in panels.iter() {
            self.glyphs.record_compute_glyphs(cmd, panel.glyphs, slot)?;
        }
        // SAFETY: as above.
        unsafe { d.cmd_begin_rendering(cmd, &rendering) };
        // The panel at the corner: its viewport is its cell.
        for panel in panels.iter().filter(|p| p.in_place()) {
            record_panel(passes, cmd, slot, panel)?;
        }
        // SAFETY: as above.
        unsafe { d.cmd_end_rendering(cmd) };
        let copied: Vec<&PanelDraw> = panels.iter().filter(|p| !p.in_place()).collect();
        let last = if copied.is_empty() && !patched {
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
                frame
                    .composer
                    .record_panel(d, cmd, image, panel.cell, background, || {
                        record_panel(passes, cmd, slot, panel)
                    })?;
            }
            if patched {
                // The captions go over the panels copied just before them.
                let after_copies = [copies_to_patches(image)];
                // SAFETY: as above.
                unsafe {
                    d.cmd_pipeline_barrier2(
                        cmd,
                        &vk::DependencyInfo::default().image_memory_barriers(&after_copies),
                    );
                }
                frame.composer.record_patches(d, cmd, image)?;
            }
            (vk::ImageLayout::TRANSFER_DST_OPTIMAL, COPY_WRITE)
        };
        if let Some(timer) = &frame.timer {
            timer.stop(cmd);
        }
        let readback = frame
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

/// The glyph renderer of the window: its formats, reversed depth with one sample (the
/// viewer's own convention), and the viewer's frames in flight.
fn renderer_desc(
    formats: TargetFormats,
    frames_in_flight: usize,
    settings: &RenderSettings,
) -> RendererDesc {
    RendererDesc {
        formats,
        options: PassOptions::default(),
        frames_in_flight,
        settings: *settings,
    }
}

/// The passes a panel is recorded with.
type PanelPasses<'a> = (
    &'a GlyphRenderer,
    (&'a UnderlayPass, &'a UnderlayShadowPass),
    &'a PeaksPass,
);

/// Records `panel`'s underlay, glyphs (with `slot`'s frame block), the underlay again
/// darkened by their shadows (where they cast any) and the peaks, drawn into an
/// attachment whose corner is the panel's (rendering has begun; colour and depth only,
/// so the receivers need no rendering of their own).
fn record_panel(
    (glyphs, (underlay, underlay_shadows), peaks): PanelPasses,
    cmd: vk::CommandBuffer,
    slot: usize,
    panel: &PanelDraw,
) -> Result<()> {
    let extent = panel.cell.extent;
    if let Some((volume, planes)) = panel.underlay {
        underlay.record(cmd, volume, planes, panel.frame.view_proj, extent);
    }
    glyphs.record_glyphs(cmd, panel.glyphs, slot)?;
    if let Some(underlay) = panel.underlay {
        let view_proj = panel.frame.view_proj;
        underlay_shadows.record(cmd, (panel.glyphs, slot), underlay, view_proj, extent)?;
    }
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
        // SAFETY: waiting for the device leaves nothing in flight that uses the pool's
        // command buffers (nor the members dropped after this body, the slots' fences and
        // semaphores among them); the device is alive while `self.ctx` is.
        unsafe {
            let _ = device.device_wait_idle();
            device.destroy_command_pool(self.pool, None);
        }
    }
}
