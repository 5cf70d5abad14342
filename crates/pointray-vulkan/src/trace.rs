//! One trace of a prepared scene into a target: the recorded `vkCmdTraceRaysKHR` between
//! two timestamps, then the copy of the output to host-visible memory.

use std::sync::Arc;
use std::time::Duration;

use ash::vk;
use pointray_scene::RenderSettings;

use crate::barrier::record_memory_barrier;
use crate::binding_table::ShaderBindingTable;
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::TraceSettings;
use crate::pipeline::{RayTracingPipeline, all_ray_stages};
use crate::prepared_scene::PreparedScene;
use crate::timestamp_pool::TimestampPool;
use crate::trace_target::{TargetBuffers, TraceTarget};

/// Checks `settings` against the device and against the integrator `pipeline` implements.
pub(crate) fn validate(
    settings: &RenderSettings,
    context: &GpuContext,
    pipeline: &RayTracingPipeline,
) -> Result<(), VulkanError> {
    let invalid = |m: String| Err(VulkanError::InvalidSettings(m));
    if settings.width == 0 || settings.height == 0 {
        return invalid(format!(
            "the image is {}x{}; both sides must be at least 1",
            settings.width, settings.height
        ));
    }
    if settings.samples_per_pixel == 0 || settings.max_depth == 0 {
        return invalid("samples per pixel and max depth must be at least 1".into());
    }
    if settings.integrator != pipeline.integrator {
        return invalid(format!(
            "this pipeline traces the {:?} integrator, not {:?}; windows trace the Whitted \
             integrator only",
            pipeline.integrator, settings.integrator
        ));
    }
    let limit = u64::from(context.ray_tracing_properties.max_ray_dispatch_invocation_count);
    if u64::from(settings.width) * u64::from(settings.height) > limit {
        return invalid(format!(
            "{}x{} pixels exceed this device's {limit} rays per dispatch",
            settings.width, settings.height
        ));
    }
    Ok(())
}

/// Records the trace between two timestamps and the copy of the pixels to host memory.
pub(crate) fn record(
    context: &GpuContext,
    command: vk::CommandBuffer,
    pipeline: &RayTracingPipeline,
    table: &ShaderBindingTable,
    target: &TargetBuffers,
    settings: &RenderSettings,
) {
    // SAFETY: `command` is recording; every bound resource outlives the submission.
    unsafe {
        if let Some(pool) = &target.timestamps {
            pool.record_start(command);
        }
        record_trace_rays(context, command, pipeline, table, target, settings);
        if let Some(pool) = &target.timestamps {
            pool.record_traced(command);
        }
        record_copy_out(context, command, target);
        if target.intersection_calls.is_some() {
            // The counts are read straight from their buffer, not copied out.
            record_memory_barrier(
                &context.device,
                command,
                (vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR, vk::AccessFlags::SHADER_WRITE),
                (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
            );
        }
    }
}

/// Records the binding of the pipeline and its resources and one `vkCmdTraceRaysKHR`.
///
/// # Safety
/// `command` is recording; every bound resource outlives the submission.
pub(crate) unsafe fn record_trace_rays(
    context: &GpuContext,
    command: vk::CommandBuffer,
    pipeline: &RayTracingPipeline,
    table: &ShaderBindingTable,
    target: &TargetBuffers,
    settings: &RenderSettings,
) {
    let push = TraceSettings::new(settings, target.output.code());
    let launch = Launch { set: target.descriptors.set, push, width: settings.width, height: settings.height };
    // SAFETY: the caller's contract.
    unsafe { record_launch(context, command, pipeline, table, &launch) };
}

/// What one `vkCmdTraceRaysKHR` binds and how many invocations it launches.
pub(crate) struct Launch {
    pub(crate) set: vk::DescriptorSet,
    pub(crate) push: TraceSettings,
    pub(crate) width: u32,
    pub(crate) height: u32,
}

/// Records the binding of the pipeline, `launch`'s set and push constants, and the trace.
///
/// # Safety
/// `command` is recording; every bound resource outlives the submission.
pub(crate) unsafe fn record_launch(
    context: &GpuContext,
    command: vk::CommandBuffer,
    pipeline: &RayTracingPipeline,
    table: &ShaderBindingTable,
    launch: &Launch,
) {
    let device = &context.device;
    let bind_point = vk::PipelineBindPoint::RAY_TRACING_KHR;
    let push = bytemuck::bytes_of(&launch.push);
    // SAFETY: the caller's contract.
    unsafe {
        device.cmd_bind_pipeline(command, bind_point, pipeline.pipeline);
        device.cmd_bind_descriptor_sets(command, bind_point, pipeline.layout, 0, &[launch.set], &[]);
        device.cmd_push_constants(command, pipeline.layout, all_ray_stages(), 0, push);
        context.ray_tracing.cmd_trace_rays(
            command,
            &table.raygen,
            &table.miss,
            &table.hit,
            &table.callable,
            launch.width,
            launch.height,
            1,
        );
    }
}

/// Records the wait for the trace, the copy of the pixels to the read-back buffer and the
/// barrier that makes them visible to the host.
///
/// # Safety
/// `command` is recording; the resources outlive the submission.
pub(crate) unsafe fn record_copy_out(
    context: &GpuContext,
    command: vk::CommandBuffer,
    target: &TargetBuffers,
) {
    // SAFETY: the caller's contract.
    unsafe {
        record_trace_done_barrier(&context.device, command);
        record_read_back(&context.device, command, target);
    }
}

/// Makes the trace's pixel writes visible to transfers that copy them.
///
/// # Safety
/// `command` is recording.
pub(crate) unsafe fn record_trace_done_barrier(device: &ash::Device, command: vk::CommandBuffer) {
    // SAFETY: the caller's contract.
    unsafe {
        record_memory_barrier(
            device,
            command,
            (vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR, vk::AccessFlags::SHADER_WRITE),
            (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::TRANSFER_READ),
        )
    };
}

/// Copies the traced pixels to the read-back buffer and makes them visible to the host.
///
/// # Safety
/// `command` is recording, after `record_trace_done_barrier`; the resources outlive the
/// submission.
pub(crate) unsafe fn record_read_back(
    device: &ash::Device,
    command: vk::CommandBuffer,
    target: &TargetBuffers,
) {
    // SAFETY: the caller's contract.
    unsafe {
        let region = vk::BufferCopy::default().size(target.written.size);
        device.cmd_copy_buffer(command, target.written.handle, target.readback.handle, &[region]);
        record_memory_barrier(
            device,
            command,
            (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::TRANSFER_WRITE),
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
    }
}

/// Traces `scene` into `target`, re-allocating it only if the size changed; returns the
/// GPU time of the trace itself.
pub(crate) fn trace_into(
    context: &Arc<GpuContext>,
    pipeline: &RayTracingPipeline,
    table: &ShaderBindingTable,
    scene: &PreparedScene,
    settings: &RenderSettings,
    target: &mut TraceTarget,
) -> Result<Option<Duration>, VulkanError> {
    validate(settings, context, pipeline)?;
    let buffers = target.bind(context, pipeline, scene, settings)?;
    context.submit_and_wait("tracing rays", |command| {
        record(context, command, pipeline, table, buffers, settings)
    })?;
    buffers.timestamps.as_ref().map(TimestampPool::trace_time).transpose()
}
