//! Ray lists: rays given one by one (a LiDAR sweep's, in its sensor's frame) cast from each
//! of several poses into a prepared scene, to their closest hits, by `ray_list.rgen` through
//! the renderer's hit groups. A `RayListTarget` keeps the buffers between casts, so that
//! casting sweep after sweep allocates only when a cast outgrows them.

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
use crate::gpu_records::{ListedRay, RayHit, RayPose, TraceSettings};
use crate::kept_buffers::kept_or_made;
use crate::pipeline::{BINDING_RAY_HITS, BINDING_RAY_LIST, BINDING_RAY_POSES, RayTracingPipeline};
use crate::prepared_scene::PreparedScene;
use crate::renderer::{TraceTiming, VulkanRenderer};
use crate::timestamp_pool::TimestampPool;
use crate::trace::{Launch, record_launch};

/// Rays a launch row holds: within every device's launch width (at least 65,535 x 128).
const LAUNCH_ROW: u32 = 1 << 16;

const RAY_BYTES: u64 = std::mem::size_of::<ListedRay>() as u64;
const HIT_BYTES: u64 = std::mem::size_of::<RayHit>() as u64;
const POSE_BYTES: u64 = std::mem::size_of::<RayPose>() as u64;

/// Reusable buffers of ray-list casts; see `VulkanRenderer::cast_rays`.
#[derive(Default)]
pub struct RayListTarget {
    buffers: Option<ListBuffers>,
    /// Hits of the last cast.
    cast: usize,
}

/// The rays of a list, its poses, and the hits of casting one from the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Counts {
    rays: u64,
    poses: u64,
}

impl Counts {
    fn hits(self) -> u64 {
        self.rays * self.poses
    }

    fn holds(self, other: Counts) -> bool {
        self.rays >= other.rays && self.poses >= other.poses
    }
}

struct ListBuffers {
    context: Arc<GpuContext>,
    /// Rays, poses and hits the buffers hold.
    capacity: Counts,
    rays: Buffer,
    poses: Buffer,
    hits: Buffer,
    descriptors: TraceDescriptors,
    timestamps: Option<TimestampPool>,
}

impl RayListTarget {
    pub fn new() -> Self {
        Self::default()
    }

    /// What each ray of the last cast met from each pose: the list's rays from the first
    /// pose, then from the second, and so on.
    pub fn hits(&self) -> &[RayHit] {
        match &self.buffers {
            Some(buffers) => &bytemuck::cast_slice(buffers.hits.read())[..self.cast],
            None => &[],
        }
    }

    /// Buffers for `counts`, made anew when the device changed or the cast outgrew them.
    fn buffers_for(
        &mut self,
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        counts: Counts,
    ) -> Result<&mut ListBuffers, VulkanError> {
        kept_or_made(
            &mut self.buffers,
            |b| Arc::ptr_eq(&b.context, context) && b.capacity.holds(counts),
            || ListBuffers::new(context, pipeline, counts),
        )
    }
}

impl ListBuffers {
    fn new(
        context: &Arc<GpuContext>,
        pipeline: &RayTracingPipeline,
        capacity: Counts,
    ) -> Result<Self, VulkanError> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let (host, readback) = (MemoryLocation::CpuToGpu, MemoryLocation::GpuToCpu);
        Ok(Self {
            context: context.clone(),
            capacity,
            rays: Buffer::new(context, "ray list", capacity.rays * RAY_BYTES, storage, host)?,
            poses: Buffer::new(context, "ray poses", capacity.poses * POSE_BYTES, storage, host)?,
            hits: Buffer::new(context, "ray hits", capacity.hits() * HIT_BYTES, storage, readback)?,
            descriptors: TraceDescriptors::new(context, pipeline)?,
            timestamps: TimestampPool::around_trace(context)?,
        })
    }

    /// Casts the uploaded list of `rays` rays from the poses `first .. first + count`; their
    /// GPU time.
    fn cast_batch(
        &mut self,
        (pipeline, table): (&RayTracingPipeline, &ShaderBindingTable),
        scene: &PreparedScene,
        push: TraceSettings,
        (rays, first, count): (u64, u64, u64),
    ) -> Result<Option<Duration>, VulkanError> {
        let range = |binding, buffer, bytes| StorageRange {
            binding,
            buffer,
            offset: first * bytes,
            range: count * bytes,
        };
        let storage = [
            StorageRange {
                binding: BINDING_RAY_LIST,
                buffer: &self.rays,
                offset: 0,
                range: rays * RAY_BYTES,
            },
            range(BINDING_RAY_POSES, &self.poses, POSE_BYTES),
            range(BINDING_RAY_HITS, &self.hits, rays * HIT_BYTES),
        ];
        self.descriptors.write(scene, &storage);
        let count = rays * count;
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

/// The device's bounds on one launch: the invocations a dispatch holds, the bytes one
/// storage binding reaches, and the alignment of a binding's offset.
fn launch_bounds(context: &GpuContext) -> (u64, u64, u64) {
    // SAFETY: the physical device belongs to the context's live instance.
    let limits = unsafe { context.instance.instance.get_physical_device_properties(context.physical) }.limits;
    let invocations = u64::from(context.ray_tracing_properties.max_ray_dispatch_invocation_count);
    (
        invocations,
        u64::from(limits.max_storage_buffer_range),
        limits.min_storage_buffer_offset_alignment.max(1),
    )
}

/// How many poses one launch casts a list of `counts.rays` rays from: as many as the device
/// holds, in whole multiples of the offset alignment when it takes several launches. An
/// error when the list alone, or its poses, are more than the launches can hold.
fn poses_per_launch(context: &GpuContext, counts: Counts) -> Result<u64, VulkanError> {
    let (invocations, reach, alignment) = launch_bounds(context);
    let refuse = |what: String| Err(VulkanError::InvalidSettings(format!("{what} on {}", context.info.name)));
    let most_rays = invocations.min(reach / RAY_BYTES).min(reach / HIT_BYTES);
    if counts.rays > most_rays {
        return refuse(format!(
            "a ray list of {} rays is more than the {most_rays} one cast holds",
            counts.rays
        ));
    }
    let most = (invocations.min(reach / HIT_BYTES) / counts.rays.max(1)).min(reach / POSE_BYTES).max(1);
    if counts.poses <= most {
        return Ok(most);
    }
    // Later launches bind the poses and hits from an offset, which must be aligned.
    match most / alignment * alignment {
        0 => refuse(format!(
            "{} poses of a list of {} rays take several launches, and one launch holds fewer than {alignment}",
            counts.poses, counts.rays
        )),
        aligned => Ok(aligned),
    }
}

impl VulkanRenderer {
    /// Casts each of `rays` from each of `poses` (each placing the list's frame in `scene`'s)
    /// to its closest hit, patches accepted by `acceptance`, into `target`; read what they met
    /// with `RayListTarget::hits`. Casts of more poses than one launch holds go in several.
    pub fn cast_rays(
        &self,
        scene: &PreparedScene,
        rays: &[ListedRay],
        poses: &[RayPose],
        acceptance: PatchAcceptance,
        target: &mut RayListTarget,
    ) -> Result<TraceTiming, VulkanError> {
        self.ensure_prepared_here(scene)?;
        let start = Instant::now();
        let pipelines = self.ray_list_pipeline()?;
        let counts = Counts { rays: rays.len() as u64, poses: poses.len() as u64 };
        let per_launch = poses_per_launch(&self.context, counts)?;
        target.cast = 0;
        let room = Counts { rays: counts.rays.max(1), poses: counts.poses.max(1) };
        let buffers = target.buffers_for(&self.context, pipelines.0, room)?;
        buffers.rays.write(bytemuck::cast_slice(rays));
        buffers.poses.write(bytemuck::cast_slice(poses));
        let push = TraceSettings::for_ray_list(acceptance, scene.buffer_layout);
        let mut gpu = Some(Duration::ZERO);
        if counts.rays > 0 {
            for first in (0..counts.poses).step_by(per_launch as usize) {
                let batch = (counts.rays, first, per_launch.min(counts.poses - first));
                let time = buffers.cast_batch(pipelines, scene, push, batch)?;
                gpu = gpu.zip(time).map(|(sum, time)| sum + time);
            }
        }
        target.cast = counts.hits() as usize;
        Ok(TraceTiming { gpu, wall: start.elapsed() })
    }
}
