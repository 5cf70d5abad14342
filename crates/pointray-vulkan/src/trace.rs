//! One trace of a prepared scene: per-trace buffers and descriptors, the recorded
//! `vkCmdTraceRaysKHR` between two timestamps, and the read-back into a `Frame`.

use std::sync::Arc;
use std::time::Duration;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;
use pointray_scene::{Frame, RenderSettings};

use crate::barrier::record_memory_barrier;
use crate::binding_table::ShaderBindingTable;
use crate::buffer::Buffer;
use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::gpu_records::{FrameUniforms, PixelRecord, TraceSettings};
use crate::pipeline::{
    BINDING_FRAME, BINDING_LIGHTS, BINDING_OBJECTS, BINDING_PIXELS, BINDING_TLAS, RayTracingPipeline,
    all_ray_stages,
};
use crate::prepared_scene::PreparedScene;

/// Per-trace resources, freed on drop (after the trace has been waited on).
pub(crate) struct TraceResources {
    context: Arc<GpuContext>,
    uniforms: Buffer,
    pixels: Buffer,
    pub(crate) readback: Buffer,
    descriptor_pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    timestamps: Option<vk::QueryPool>,
}

impl Drop for TraceResources {
    fn drop(&mut self) {
        // SAFETY: the trace that used them has completed.
        unsafe {
            self.context.device.destroy_descriptor_pool(self.descriptor_pool, None);
            if let Some(pool) = self.timestamps {
                self.context.device.destroy_query_pool(pool, None);
            }
        }
    }
}

pub(crate) fn validate(settings: &RenderSettings, context: &GpuContext) -> Result<(), VulkanError> {
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
    let limit = u64::from(context.ray_tracing_properties.max_ray_dispatch_invocation_count);
    if u64::from(settings.width) * u64::from(settings.height) > limit {
        return invalid(format!(
            "{}x{} pixels exceed this device's {limit} rays per dispatch",
            settings.width, settings.height
        ));
    }
    Ok(())
}

pub(crate) fn create_resources(
    context: &Arc<GpuContext>,
    pipeline: &RayTracingPipeline,
    scene: &PreparedScene,
    settings: &RenderSettings,
) -> Result<TraceResources, VulkanError> {
    let uniforms = FrameUniforms::new(&scene.camera, &scene.background, scene.light_count, scene.ray_epsilon);
    let uniforms = Buffer::host_with_data(
        context,
        "frame uniforms",
        bytemuck::bytes_of(&uniforms),
        vk::BufferUsageFlags::UNIFORM_BUFFER,
    )?;
    let pixel_bytes =
        u64::from(settings.width) * u64::from(settings.height) * std::mem::size_of::<PixelRecord>() as u64;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
    let pixels = Buffer::new(context, "pixel records", pixel_bytes, usage, MemoryLocation::GpuOnly)?;
    let readback = Buffer::new(
        context,
        "pixel read-back",
        pixel_bytes,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let sizes = [
        vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .descriptor_count(1),
        vk::DescriptorPoolSize::default().ty(vk::DescriptorType::UNIFORM_BUFFER).descriptor_count(1),
        vk::DescriptorPoolSize::default().ty(vk::DescriptorType::STORAGE_BUFFER).descriptor_count(3),
    ];
    let pool_info = vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes);
    let device = &context.device;
    // SAFETY: the device is alive; the pool is destroyed with the resources.
    let descriptor_pool =
        unsafe { device.create_descriptor_pool(&pool_info, None) }.during("creating a descriptor pool")?;
    let mut resources = TraceResources {
        context: context.clone(),
        uniforms,
        pixels,
        readback,
        descriptor_pool,
        set: vk::DescriptorSet::null(),
        timestamps: None,
    };
    let layouts = [pipeline.set_layout];
    let allocate =
        vk::DescriptorSetAllocateInfo::default().descriptor_pool(descriptor_pool).set_layouts(&layouts);
    // SAFETY: the pool has room for exactly this set.
    resources.set =
        unsafe { device.allocate_descriptor_sets(&allocate) }.during("allocating a descriptor set")?[0];
    write_descriptors(device, &resources, scene);
    if context.timestamp_period_ns.is_some() {
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(2);
        // SAFETY: the device is alive.
        resources.timestamps =
            Some(unsafe { device.create_query_pool(&info, None) }.during("creating a timestamp pool")?);
    }
    Ok(resources)
}

fn write_descriptors(device: &ash::Device, resources: &TraceResources, scene: &PreparedScene) {
    let structures = [scene.tlas.handle];
    let mut tlas =
        vk::WriteDescriptorSetAccelerationStructureKHR::default().acceleration_structures(&structures);
    let whole =
        |buffer: &Buffer| [vk::DescriptorBufferInfo::default().buffer(buffer.handle).range(vk::WHOLE_SIZE)];
    let (frame, objects, lights, pixels) =
        (whole(&resources.uniforms), whole(&scene.objects), whole(&scene.lights), whole(&resources.pixels));
    let write = |binding, ty| {
        vk::WriteDescriptorSet::default().dst_set(resources.set).dst_binding(binding).descriptor_type(ty)
    };
    let storage = vk::DescriptorType::STORAGE_BUFFER;
    let writes = [
        write(BINDING_TLAS, vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .descriptor_count(1)
            .push_next(&mut tlas),
        write(BINDING_FRAME, vk::DescriptorType::UNIFORM_BUFFER).buffer_info(&frame),
        write(BINDING_OBJECTS, storage).buffer_info(&objects),
        write(BINDING_LIGHTS, storage).buffer_info(&lights),
        write(BINDING_PIXELS, storage).buffer_info(&pixels),
    ];
    // SAFETY: every written resource is alive; the set is not in use.
    unsafe { device.update_descriptor_sets(&writes, &[]) };
}

/// Records the trace between two timestamps and the copy of the pixels to host memory.
pub(crate) fn record(
    context: &GpuContext,
    command: vk::CommandBuffer,
    pipeline: &RayTracingPipeline,
    table: &ShaderBindingTable,
    resources: &TraceResources,
    settings: &RenderSettings,
) {
    let device = &context.device;
    // SAFETY: `command` is recording; every bound resource outlives the submission.
    unsafe {
        if let Some(pool) = resources.timestamps {
            device.cmd_reset_query_pool(command, pool, 0, 2);
            device.cmd_write_timestamp(command, vk::PipelineStageFlags::TOP_OF_PIPE, pool, 0);
        }
        record_trace_rays(context, command, pipeline, table, resources, settings);
        if let Some(pool) = resources.timestamps {
            device.cmd_write_timestamp(command, vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR, pool, 1);
        }
        record_copy_out(context, command, resources);
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
    resources: &TraceResources,
    settings: &RenderSettings,
) {
    let device = &context.device;
    let bind_point = vk::PipelineBindPoint::RAY_TRACING_KHR;
    let push = TraceSettings::from(settings);
    // SAFETY: the caller's contract.
    unsafe {
        device.cmd_bind_pipeline(command, bind_point, pipeline.pipeline);
        device.cmd_bind_descriptor_sets(command, bind_point, pipeline.layout, 0, &[resources.set], &[]);
        device.cmd_push_constants(command, pipeline.layout, all_ray_stages(), 0, bytemuck::bytes_of(&push));
        context.ray_tracing.cmd_trace_rays(
            command,
            &table.raygen,
            &table.miss,
            &table.hit,
            &table.callable,
            settings.width,
            settings.height,
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
    resources: &TraceResources,
) {
    let device = &context.device;
    // SAFETY: the caller's contract.
    unsafe {
        record_memory_barrier(
            device,
            command,
            (vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR, vk::AccessFlags::SHADER_WRITE),
            (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::TRANSFER_READ),
        );
        let region = vk::BufferCopy::default().size(resources.pixels.size);
        device.cmd_copy_buffer(command, resources.pixels.handle, resources.readback.handle, &[region]);
        record_memory_barrier(
            device,
            command,
            (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::TRANSFER_WRITE),
            (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
        );
    }
}

/// Time the GPU spent between the two timestamps around the trace.
fn gpu_time(context: &GpuContext, resources: &TraceResources) -> Result<Option<Duration>, VulkanError> {
    let (Some(pool), Some(period)) = (resources.timestamps, context.timestamp_period_ns) else {
        return Ok(None);
    };
    let mut ticks = [0u64; 2];
    // SAFETY: both timestamps were written by a completed submission.
    unsafe {
        context.device.get_query_pool_results(
            pool,
            0,
            &mut ticks,
            vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
        )
    }
    .during("reading trace timestamps")?;
    let nanoseconds = ticks[1].saturating_sub(ticks[0]) as f64 * f64::from(period);
    Ok(Some(Duration::from_nanos(nanoseconds as u64)))
}

fn frame_from_pixels(settings: &RenderSettings, pixels: &[PixelRecord]) -> Frame {
    let hit = |p: &PixelRecord| p.normal_depth[3] >= 0.0;
    Frame {
        width: settings.width,
        height: settings.height,
        color: pixels.iter().map(|p| Vec3::from_slice(&p.color[..3])).collect(),
        depth: pixels.iter().map(|p| if hit(p) { p.normal_depth[3] } else { f32::INFINITY }).collect(),
        normal: pixels
            .iter()
            .map(|p| if hit(p) { Vec3::from_slice(&p.normal_depth[..3]) } else { Vec3::ZERO })
            .collect(),
        instance_id: pixels.iter().map(|p| if hit(p) { p.ids[0] } else { Frame::MISS }).collect(),
        primitive_id: pixels.iter().map(|p| if hit(p) { p.ids[1] } else { Frame::MISS }).collect(),
    }
}

/// Traces `scene` once; returns the frame and the GPU time of the trace itself.
pub(crate) fn trace(
    context: &Arc<GpuContext>,
    pipeline: &RayTracingPipeline,
    table: &ShaderBindingTable,
    scene: &PreparedScene,
    settings: &RenderSettings,
) -> Result<(Frame, Option<Duration>), VulkanError> {
    validate(settings, context)?;
    let resources = create_resources(context, pipeline, scene, settings)?;
    context.submit_and_wait("tracing rays", |command| {
        record(context, command, pipeline, table, &resources, settings)
    })?;
    let gpu = gpu_time(context, &resources)?;
    let pixels: Vec<PixelRecord> = bytemuck::pod_collect_to_vec(resources.readback.read());
    Ok((frame_from_pixels(settings, &pixels), gpu))
}
