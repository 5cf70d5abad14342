//! GPU timestamps around recorded work: a query pool, destroyed on drop (after its
//! submission was waited on).

use std::sync::Arc;
use std::time::Duration;

use ash::vk;

use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};

pub(crate) struct TimestampPool {
    context: Arc<GpuContext>,
    pub(crate) handle: vk::QueryPool,
    pub(crate) count: u32,
}

impl TimestampPool {
    pub(crate) fn new(context: &Arc<GpuContext>, count: u32) -> Result<Self, VulkanError> {
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(count);
        // SAFETY: the device is alive; the pool is destroyed in Drop.
        let handle =
            unsafe { context.device.create_query_pool(&info, None) }.during("creating a timestamp pool")?;
        Ok(Self { context: context.clone(), handle, count })
    }

    /// A pool of two timestamps, one before and one after a trace; `None` where the queue
    /// has no timestamps.
    pub(crate) fn around_trace(context: &Arc<GpuContext>) -> Result<Option<Self>, VulkanError> {
        context.timestamp_period_ns.map(|_| Self::new(context, 2)).transpose()
    }

    pub(crate) fn ticks(&self) -> Result<Vec<u64>, VulkanError> {
        let mut ticks = vec![0u64; self.count as usize];
        // SAFETY: every query was written by a completed submission.
        unsafe {
            self.context.device.get_query_pool_results(
                self.handle,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .during("reading GPU timestamps")?;
        Ok(ticks)
    }

    /// Records the reset of the pool and the timestamp before a trace.
    ///
    /// # Safety
    /// `command` is recording; the pool outlives the submission.
    pub(crate) unsafe fn record_start(&self, command: vk::CommandBuffer) {
        let device = &self.context.device;
        // SAFETY: the caller's contract.
        unsafe {
            device.cmd_reset_query_pool(command, self.handle, 0, self.count);
            device.cmd_write_timestamp(command, vk::PipelineStageFlags::TOP_OF_PIPE, self.handle, 0);
        }
    }

    /// Records the timestamp once ray tracing has drained.
    ///
    /// # Safety
    /// `command` is recording, after `record_start`; the pool outlives the submission.
    pub(crate) unsafe fn record_traced(&self, command: vk::CommandBuffer) {
        let stage = vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR;
        // SAFETY: the caller's contract.
        unsafe { self.context.device.cmd_write_timestamp(command, stage, self.handle, 1) };
    }

    /// The GPU time between the first two timestamps.
    pub(crate) fn trace_time(&self) -> Result<Duration, VulkanError> {
        let ticks = self.ticks()?;
        Ok(span(&self.context, ticks[0], ticks[1]))
    }
}

/// The time between two timestamps of `context`'s queue.
pub(crate) fn span(context: &GpuContext, from: u64, to: u64) -> Duration {
    let period_ns = context.timestamp_period_ns.unwrap_or(0.0);
    Duration::from_secs_f64(to.saturating_sub(from) as f64 * f64::from(period_ns) * 1e-9)
}

impl Drop for TimestampPool {
    fn drop(&mut self) {
        // SAFETY: the submission that used the pool has completed.
        unsafe { self.context.device.destroy_query_pool(self.handle, None) };
    }
}
