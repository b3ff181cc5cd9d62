//! The window's frames in flight: one [`FrameSlot`] per frame the viewer records ahead of
//! the GPU, holding everything a frame writes (command buffer, fence, image-acquired
//! semaphore, depth buffer, the montage's offscreen target and the colour bar's staging
//! buffer, timer queries, the capture buffer). A slot is reused only after its fence
//! says its previous frame completed, so the other slots' frames may still be on the GPU
//! meanwhile; nothing is shared between slots except what no frame writes (the uploaded
//! glyphs, the underlay's volume, the pipelines).
//!
//! The render-finished semaphores are the swapchain's, one per image, not per slot: an
//! image is acquired again only after its presentation, which waited on that semaphore,
//! so reusing it is safe, where a per-slot one could still be held by the presentation
//! engine.
use super::compose::Composer;
use ash::vk;
use glyphcast::error::{Result, VkContext};
use glyphcast::vk::{Buffer, DeviceContext, Gpu, GpuTimer, Image};
use gpu_allocator::MemoryLocation;

/// Frames the viewer records ahead of the GPU unless told otherwise (`view
/// --frames-in-flight`).
pub const FRAMES_IN_FLIGHT: usize = 2;

/// What one frame in flight writes.
pub struct FrameSlot {
    pub cmd: vk::CommandBuffer,
    /// Signalled by the acquire of this slot's swapchain image.
    pub acquired: vk::Semaphore,
    /// Signalled when this slot's last submission completed (made signalled: none yet).
    pub done: vk::Fence,
    /// The window's depth buffer for this slot's frames.
    pub depth: Option<Image>,
    /// The montage panels' offscreen target and the strip's staging buffer.
    pub composer: Composer,
    pub timer: Option<GpuTimer>,
    /// The last submission wrote timestamps.
    pub timed: bool,
    /// The read-back of what the window showed (`--capture-window`).
    pub capture: Option<(Buffer, vk::Extent2D)>,
    ctx: DeviceContext,
}

impl FrameSlot {
    /// A slot with its command buffer from `pool` (of `gpu`'s device).
    pub fn new(gpu: &Gpu, pool: vk::CommandPool) -> Result<FrameSlot> {
        let device = gpu.device();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
        // SAFETY: valid device, pool and create infos; the semaphore and fence are
        // destroyed in Drop, the command buffer with its pool.
        let (cmd, acquired, done) = unsafe {
            (
                device
                    .allocate_command_buffers(&alloc)
                    .vk("vkAllocateCommandBuffers")?[0],
                device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                    .vk("vkCreateSemaphore")?,
                device.create_fence(&signalled, None).vk("vkCreateFence")?,
            )
        };
        Ok(FrameSlot {
            cmd,
            acquired,
            done,
            depth: None,
            composer: Composer::default(),
            timer: GpuTimer::new(gpu)?,
            timed: false,
            capture: None,
            ctx: gpu.context().clone(),
        })
    }

    /// Waits until this slot's last submission completed; returns its GPU time if it was
    /// timed.
    pub fn wait(&mut self) -> Result<Option<f64>> {
        // SAFETY: the fence belongs to this device.
        unsafe {
            self.ctx
                .device()
                .wait_for_fences(&[self.done], true, u64::MAX)
                .vk("vkWaitForFences")?;
        }
        if std::mem::take(&mut self.timed) {
            return self.timer.as_ref().map(GpuTimer::elapsed_ms).transpose();
        }
        Ok(None)
    }

    /// Whether this slot's last submission is still on the GPU.
    pub fn in_flight(&self) -> Result<bool> {
        // SAFETY: the fence belongs to this device.
        let signalled =
            unsafe { self.ctx.device().get_fence_status(self.done) }.vk("vkGetFenceStatus")?;
        Ok(!signalled)
    }

    /// Makes the slot's depth buffer for a swapchain of `extent`.
    pub fn make_depth(&mut self, format: vk::Format, extent: vk::Extent2D) -> Result<()> {
        self.depth = None;
        self.depth = Some(Image::new(
            &self.ctx,
            "window depth",
            extent,
            format,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?);
        Ok(())
    }

    /// Makes the capture buffer for a swapchain of `extent`, if it has another size.
    pub fn ensure_capture(&mut self, extent: vk::Extent2D) -> Result<()> {
        if self.capture.as_ref().is_some_and(|(_, e)| *e == extent) {
            return Ok(());
        }
        self.capture = None;
        let bytes = 4 * u64::from(extent.width) * u64::from(extent.height);
        let buffer = Buffer::new(
            &self.ctx,
            "window capture",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.capture = Some((buffer, extent));
        Ok(())
    }
}

impl Drop for FrameSlot {
    fn drop(&mut self) {
        let device = self.ctx.device();
        // SAFETY: the presenter waits for the device before its slots go, so neither
        // object is in use; the device is alive while `self.ctx` is.
        unsafe {
            device.destroy_fence(self.done, None);
            device.destroy_semaphore(self.acquired, None);
        }
    }
}
