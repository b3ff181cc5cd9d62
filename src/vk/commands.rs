//! One-shot command buffers: record, submit, wait. Enough for headless rendering, tests
//! and benchmarks; a viewer brings its own frame loop.
use super::DeviceContext;
use crate::error::{Result, VkContext};
use ash::vk;

/// A command pool and fence for recording, submitting and waiting on one command buffer
/// at a time.
pub struct OneShot {
    pool: vk::CommandPool,
    fence: vk::Fence,
    /// Keeps the device alive as long as the pool and fence.
    ctx: DeviceContext,
}

impl OneShot {
    /// A pool on the queue family of `gpu`, and its fence.
    pub fn new(gpu: &super::Gpu) -> Result<OneShot> {
        let device = gpu.device();
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        // SAFETY: as above.
        let fence = match unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) } {
            Ok(f) => f,
            Err(result) => {
                // SAFETY: the pool has no command buffers in use.
                unsafe { device.destroy_command_pool(pool, None) };
                return Err(crate::Error::Vulkan {
                    call: "vkCreateFence",
                    result,
                });
            }
        };
        Ok(OneShot {
            pool,
            fence,
            ctx: gpu.context().clone(),
        })
    }

    fn device(&self) -> &ash::Device {
        self.ctx.device()
    }

    /// Records with `record`, submits to `gpu.queue` and waits for completion.
    pub fn run<T>(
        &self,
        gpu: &super::Gpu,
        record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
    ) -> Result<T> {
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device.
        let cmd = unsafe { self.device().allocate_command_buffers(&alloc) }
            .vk("vkAllocateCommandBuffers")?[0];
        let result = self.record_and_submit(gpu, cmd, record);
        // SAFETY: the submission has completed (or never happened) when we get here.
        unsafe { self.device().free_command_buffers(self.pool, &[cmd]) };
        result
    }

    fn record_and_submit<T>(
        &self,
        gpu: &super::Gpu,
        cmd: vk::CommandBuffer,
        record: impl FnOnce(vk::CommandBuffer) -> Result<T>,
    ) -> Result<T> {
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: `cmd` is a fresh primary command buffer of this device.
        unsafe { self.device().begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        let value = record(cmd)?;
        // SAFETY: recording was begun above.
        unsafe { self.device().end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the fence is unsignalled and the command buffer is executable.
        unsafe {
            self.device()
                .queue_submit2(gpu.queue, &submit, self.fence)
                .vk("vkQueueSubmit2")?;
            self.device()
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .vk("vkWaitForFences")?;
            self.device()
                .reset_fences(&[self.fence])
                .vk("vkResetFences")?;
        }
        Ok(value)
    }
}

impl Drop for OneShot {
    fn drop(&mut self) {
        // SAFETY: `run` waits for every submission, so nothing is in flight; the device is
        // alive while `self.ctx` is.
        unsafe {
            self.device().destroy_fence(self.fence, None);
            self.device().destroy_command_pool(self.pool, None);
        }
    }
}
