//! GPU time of a span of commands from two timestamp queries, scaled by the device's
//! timestamp period. Wall clocks around a submit would time the driver and the queue too.
use super::DeviceContext;
use crate::error::{Result, VkContext};
use ash::vk;

/// Two timestamp queries around a span of commands.
pub struct GpuTimer {
    /// Keeps the device alive as long as the query pool.
    ctx: DeviceContext,
    pool: vk::QueryPool,
    period_ns: f64,
    valid_bits: u32,
}

impl GpuTimer {
    /// `None` if the queue cannot write timestamps.
    pub fn new(gpu: &super::Gpu) -> Result<Option<GpuTimer>> {
        if gpu.info.timestamp_valid_bits == 0 || gpu.context().timestamp_period_ns() <= 0.0 {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2);
        // SAFETY: valid create info; destroyed in Drop.
        let pool =
            unsafe { gpu.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        Ok(Some(GpuTimer {
            ctx: gpu.context().clone(),
            pool,
            period_ns: gpu.context().timestamp_period_ns() as f64,
            valid_bits: gpu.info.timestamp_valid_bits,
        }))
    }

    /// Resets the queries and writes the first timestamp once everything before is done.
    pub fn start(&self, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is recording outside a render pass instance; the pool is alive.
        unsafe {
            self.ctx.device().cmd_reset_query_pool(cmd, self.pool, 0, 2);
            self.ctx.device().cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                0,
            );
        }
    }

    /// Writes the second timestamp after all earlier commands complete.
    pub fn stop(&self, cmd: vk::CommandBuffer) {
        // SAFETY: as in `start`.
        unsafe {
            self.ctx.device().cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                1,
            );
        }
    }

    /// Milliseconds between the two timestamps; call after the submission completed.
    pub fn elapsed_ms(&self) -> Result<f64> {
        let mut stamps = [0u64; 2];
        // SAFETY: both queries were written by a completed submission.
        unsafe {
            self.ctx.device().get_query_pool_results(
                self.pool,
                0,
                &mut stamps,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        let mask = if self.valid_bits >= 64 {
            u64::MAX
        } else {
            (1u64 << self.valid_bits) - 1
        };
        let ticks = (stamps[1] & mask).wrapping_sub(stamps[0] & mask) & mask;
        Ok(ticks as f64 * self.period_ns * 1e-6)
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        // SAFETY: the submissions that used the pool have completed; the device is alive
        // while `self.ctx` is.
        unsafe { self.ctx.device().destroy_query_pool(self.pool, None) };
    }
}
