//! Ray lists: rays given one by one (a LiDAR sweep's, say) cast into a prepared scene to
//! their closest hits by `ray_list.rgen`, through the renderer's hit groups. A
//! `RayListTarget` keeps the list's buffers between casts, so that casting sweep after sweep
//! allocates only when a list outgrows them.

use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::MemoryLocation;
use pointray_kernels::PatchAcceptance;

use crate::barrier::record_memory_barrier;
use crate::binding_table::ShaderBindingTable;
use crate::buffer::Buffer;
use crate::context::GpuContext;
use crate::descriptor_set::{StorageRange, TraceDescriptors};
use crate::error::VulkanError;
use crate::gpu_records::{ListedRay, RayHit, TraceSettings};
use crate::kept_buffers::kept_or_made;
use crate::pipeline::{BINDING_RAY_HITS, BINDING_RAY_LIST, RayTracingPipeline};
use crate::prepared_scene::PreparedScene;
use crate::renderer::{TraceTiming, VulkanRenderer};
use crate::timestamp_pool::TimestampPool;
use crate::trace::{Launch, record_launch};

/// Rays a launch row holds: within every device's launch width (at least 65,535 x 128).
const LAUNCH_ROW: u32 = 1 << 16;

const RAY_BYTES: u64 = std::mem::size_of::<ListedRay>() as u64;
const HIT_BYTES: u64 = std::mem::size_of::<RayHit>() as u64;

/// Reusable buffers of ray-list casts; see `VulkanRenderer::cast_rays`.
#[derive(Default)]
pub struct RayListTarget {
    buffers: Option<ListBuffers>,
    /// Rays in the last cast.
    cast: usize,
}

struct ListBuffers {
    context: Arc<GpuContext>,
    capacity: u64,
    rays: Buffer,
    hits: Buffer,
    descriptors: TraceDescriptors,
    timestamps: Option<TimestampPool>,
}

impl RayListTarget {
    pub fn new() -> Self {
        Self::default()
    }

    /// What each ray of the last cast met, in the list's order.
    pub fn hits(&self) -> &[RayHit] {
        match &self.buffers {
            Some(buffers) => &bytemuck::cast_slice(buffers.hits.read())[..self.cast],
            None => &[],
        }
    }

    /// Buffers for `rays` rays, made anew when the device changed or the list outgrew them.
    fn buffers_for(
        &mut self,
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        rays: u64,
    ) -> Result<&mut ListBuffers, VulkanError> {
        kept_or_made(
            &mut self.buffers,
            |b| Arc::ptr_eq(&b.context, context) && b.capacity >= rays,
            || ListBuffers::new(context, pipeline, rays),
        )
    }
}

impl ListBuffers {
    fn new(
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        capacity: u64,
    ) -> Result<Self, VulkanError> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(Self {
            context: context.clone(),
            capacity,
            rays: Buffer::new(context, "ray list", capacity * RAY_BYTES, storage, MemoryLocation::CpuToGpu)?,
            hits: Buffer::new(context, "ray hits", capacity * HIT_BYTES, storage, MemoryLocation::GpuToCpu)?,
            descriptors: TraceDescriptors::new(context, pipeline)?,
            timestamps: TimestampPool::around_trace(context)?,
        })
    }

    /// Casts the rays `first .. first + count` of the uploaded list; their GPU time.
    fn cast_batch(
        &mut self,
        (pipeline, table): (&RayTracingPipeline, &ShaderBindingTable),
        scene: &PreparedScene,
        push: TraceSettings,
        (first, count): (u64, u64),
    ) -> Result<Option<Duration>, VulkanError> {
        let range = |binding, buffer, bytes| StorageRange {
            binding,
            buffer,
            offset: first * bytes,
            range: count * bytes,
        };
        let storage =
            [range(BINDING_RAY_LIST, &self.rays, RAY_BYTES), range(BINDING_RAY_HITS, &self.hits, HIT_BYTES)];
        self.descriptors.write(scene, &storage);
        let width = count.min(u64::from(LAUNCH_ROW)) as u32;
        let launch = Launch {
            set: self.descriptors.set,
            push,
            width,
            height: count.div_ceil(u64::from(width)) as u32,
        };
        let context = &self.context;
        context.submit_and_wait("casting a ray list", |command| {
            // SAFETY: `command` is recording; the buffers, set and pool outlive the submission.
            unsafe {
                if let Some(pool) = &self.timestamps {
                    pool.record_start(command);
                }
                record_launch(context, command, pipeline, table, &launch);
                if let Some(pool) = &self.timestamps {
                    pool.record_traced(command);
                }
                record_memory_barrier(
                    &context.device,
                    command,
                    (vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR, vk::AccessFlags::SHADER_WRITE),
                    (vk::PipelineStageFlags::HOST, vk::AccessFlags::HOST_READ),
                );
            }
        })?;
        self.timestamps.as_ref().map(TimestampPool::trace_time).transpose()
    }
}

/// The most rays one launch casts: within the device's invocations a dispatch and the bytes
/// a storage binding reach, in whole launch rows.
fn batch_rays(context: &GpuContext) -> u64 {
    // SAFETY: the physical device belongs to the context's live instance.
    let limits = unsafe { context.instance.instance.get_physical_device_properties(context.physical) }.limits;
    let invocations = u64::from(context.ray_tracing_properties.max_ray_dispatch_invocation_count);
    let reach = u64::from(limits.max_storage_buffer_range) / RAY_BYTES;
    let row = u64::from(LAUNCH_ROW);
    (invocations.min(reach) / row).max(1) * row
}

impl VulkanRenderer {
    /// Casts each of `rays` (in `scene`'s frame) to its closest hit, patches accepted by
    /// `acceptance`, into `target`; read what they met with `RayListTarget::hits`. Lists
    /// longer than one launch holds go in several.
    pub fn cast_rays(
        &self,
        scene: &PreparedScene,
        rays: &[ListedRay],
        acceptance: PatchAcceptance,
        target: &mut RayListTarget,
    ) -> Result<TraceTiming, VulkanError> {
        self.ensure_prepared_here(scene)?;
        let start = Instant::now();
        let pipelines = self.ray_list_pipeline()?;
        let count = rays.len() as u64;
        target.cast = 0;
        let buffers = target.buffers_for(&self.context, pipelines.0, count.max(1))?;
        buffers.rays.write(bytemuck::cast_slice(rays));
        let push = TraceSettings::for_ray_list(acceptance, scene.buffer_layout);
        let batch = batch_rays(&self.context);
        let mut gpu = Some(Duration::ZERO);
        for first in (0..count).step_by(batch as usize) {
            let time = buffers.cast_batch(pipelines, scene, push, (first, batch.min(count - first)))?;
            gpu = gpu.zip(time).map(|(sum, time)| sum + time);
        }
        target.cast = rays.len();
        Ok(TraceTiming { gpu, wall: start.elapsed() })
    }
}
