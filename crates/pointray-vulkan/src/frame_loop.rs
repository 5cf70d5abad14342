//! The benchmark's frame loop: many frames of one prepared scene in one submission, each
//! between GPU timestamps, with the copy-out recorded but no per-frame read-back on the host.

use std::time::{Duration, Instant};

use ash::vk;
use pointray_scene::RenderSettings;

use crate::barrier::record_memory_barrier;
use crate::binding_table::ShaderBindingTable;
use crate::error::VulkanError;
use crate::pipeline::RayTracingPipeline;
use crate::prepared_scene::PreparedScene;
use crate::renderer::VulkanRenderer;
use crate::timestamp_pool::{TimestampPool, span};
use crate::trace::{record_copy_out, record_trace_rays, validate};
use crate::trace_target::{PixelOutput, TargetBuffers, TraceTarget};

/// Timestamps per frame: start, trace done, copy-out done.
const STAMPS_PER_FRAME: u32 = 3;

/// GPU times of each frame of a loop, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameLoopTimes {
    /// From the frame's start to the end of its `vkCmdTraceRaysKHR`.
    pub trace: Vec<Duration>,
    /// From the frame's start to the end of the copy of its pixels to host-visible memory.
    pub frame: Vec<Duration>,
    /// Host wall time of the whole loop: recording, submission and the wait.
    pub wall: Duration,
}

impl VulkanRenderer {
    /// Traces `frames` frames of `scene` back to back in one submission and returns each
    /// frame's GPU times. Each frame's `output` is copied to host-visible memory, as a viewer
    /// would, but not converted on the host. Needs a queue with timestamps.
    pub fn trace_frames(
        &self,
        scene: &PreparedScene,
        settings: &RenderSettings,
        frames: u32,
        output: PixelOutput,
    ) -> Result<FrameLoopTimes, VulkanError> {
        self.ensure_prepared_here(scene)?;
        let (pipeline, table) = self.pipeline_for(settings.integrator)?;
        validate(settings, &self.context, pipeline)?;
        if self.context.timestamp_period_ns.is_none() {
            return Err(VulkanError::InvalidSettings(format!(
                "{} has no timestamps on its compute queue; the frame loop times with them",
                self.context.info.name
            )));
        }
        if frames == 0 {
            return Err(VulkanError::InvalidSettings("the frame loop needs at least one frame".into()));
        }
        let mut target = TraceTarget::new(output);
        let buffers = target.bind(&self.context, pipeline, scene, settings)?;
        let pool = TimestampPool::new(&self.context, frames * STAMPS_PER_FRAME)?;
        let started = Instant::now();
        self.context.submit_and_wait("tracing the frame loop", |command| {
            self.record_frames(command, (pipeline, table), buffers, &pool, settings, frames)
        })?;
        let wall = started.elapsed();
        let ticks = pool.ticks()?;
        let span = |from: u64, to: u64| span(&self.context, from, to);
        let per_frame = ticks.chunks_exact(STAMPS_PER_FRAME as usize);
        Ok(FrameLoopTimes {
            trace: per_frame.clone().map(|t| span(t[0], t[1])).collect(),
            frame: per_frame.map(|t| span(t[0], t[2])).collect(),
            wall,
        })
    }

    fn record_frames(
        &self,
        command: vk::CommandBuffer,
        (pipeline, table): (&RayTracingPipeline, &ShaderBindingTable),
        target: &TargetBuffers,
        pool: &TimestampPool,
        settings: &RenderSettings,
        frames: u32,
    ) {
        let device = &self.context.device;
        // A frame starts once everything before it is done (ALL_COMMANDS), so frames never
        // overlap in the timings; the trace ends when ray tracing has drained.
        let all = vk::PipelineStageFlags::ALL_COMMANDS;
        // SAFETY: `command` is recording; the target and the pool outlive the submission.
        unsafe {
            device.cmd_reset_query_pool(command, pool.handle, 0, pool.count);
            for frame in 0..frames {
                let first = frame * STAMPS_PER_FRAME;
                device.cmd_write_timestamp(command, all, pool.handle, first);
                record_trace_rays(&self.context, command, pipeline, table, target, settings);
                let traced = vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR;
                device.cmd_write_timestamp(command, traced, pool.handle, first + 1);
                record_copy_out(&self.context, command, target);
                device.cmd_write_timestamp(command, all, pool.handle, first + 2);
                record_next_frame_barrier(device, command);
            }
        }
    }
}

/// The next frame's trace rewrites the pixels this frame's copy reads, and its copy rewrites
/// the read-back buffer.
///
/// # Safety
/// `command` is recording.
unsafe fn record_next_frame_barrier(device: &ash::Device, command: vk::CommandBuffer) {
    // SAFETY: the caller's contract.
    unsafe {
        record_memory_barrier(
            device,
            command,
            (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::TRANSFER_WRITE),
            (
                vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR | vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            ),
        )
    };
}
