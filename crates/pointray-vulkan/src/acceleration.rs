//! Bottom- and top-level acceleration structures (METHOD.md §3): one BLAS per point set (or per
//! tile of a large one) whose single AABB geometry holds its patch boxes, one triangle BLAS
//! per mesh, one TLAS.

use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::barrier::record_memory_barrier;
use crate::buffer::{Buffer, addressable};
use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};

/// How a point set's boxes are split into BLAS geometries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BlasLayout {
    /// One geometry holding every box (the paper's layout).
    #[default]
    OneGeometry,
    /// One geometry per box: the ablation the paper measured 3.3x slower.
    GeometryPerAabb,
    /// One geometry whose boxes each bound this many consecutive patches (2 or more), which
    /// one intersection call tests in turn: fewer, larger boxes, so a smaller and shallower
    /// BVH. Prep stores patches along a Morton curve, so a run of them lies close together.
    PatchGroups(u32),
}

impl BlasLayout {
    /// The layout that groups `patches_per_box` patches a box (one geometry either way).
    pub fn grouping(patches_per_box: u32) -> Self {
        if patches_per_box > 1 { Self::PatchGroups(patches_per_box) } else { Self::OneGeometry }
    }

    /// How many consecutive patches one box bounds.
    pub fn patches_per_box(self) -> u32 {
        match self {
            Self::PatchGroups(patches) => patches.max(1),
            Self::OneGeometry | Self::GeometryPerAabb => 1,
        }
    }

    /// Boxes in the bottom level of `patches` patches.
    pub fn boxes(self, patches: usize) -> usize {
        patches.div_ceil(self.patches_per_box() as usize)
    }
}

/// Compaction is kept only when it saves at least this fraction of the memory.
const COMPACTION_MIN_SAVING: f64 = 0.1;

/// An acceleration structure and the buffer that stores it.
pub(crate) struct AccelerationStructure {
    context: Arc<GpuContext>,
    pub(crate) handle: vk::AccelerationStructureKHR,
    pub(crate) address: vk::DeviceAddress,
    /// Wall time of the build, compaction included (its inputs are already on the GPU).
    pub(crate) build_time: Duration,
    /// GPU bytes the build held at its peak besides its input (`build_peak`).
    pub(crate) build_bytes: u64,
    _storage: Buffer,
}

impl AccelerationStructure {
    /// Bytes of GPU memory holding the structure (after compaction, if it was compacted).
    pub(crate) fn size(&self) -> u64 {
        self._storage.size
    }
}

impl Drop for AccelerationStructure {
    fn drop(&mut self) {
        // SAFETY: no GPU work using the structure is pending (every submit is waited on).
        unsafe { self.context.acceleration.destroy_acceleration_structure(self.handle, None) };
    }
}

/// What one build needs: its geometries and, per geometry, the primitive range.
pub(crate) struct BuildInput<'a> {
    pub(crate) ty: vk::AccelerationStructureTypeKHR,
    pub(crate) geometries: Vec<vk::AccelerationStructureGeometryKHR<'a>>,
    pub(crate) ranges: Vec<vk::AccelerationStructureBuildRangeInfoKHR>,
}

/// A BLAS over the boxes of `patches` patches in `layout` (`VkAabbPositionsKHR`, 24 bytes
/// each) at `aabbs`.
pub(crate) fn aabb_input<'a>(aabbs: vk::DeviceAddress, patches: usize, layout: BlasLayout) -> BuildInput<'a> {
    let count = layout.boxes(patches) as u32;
    let geometry = |address| {
        let aabbs = vk::AccelerationStructureGeometryAabbsDataKHR::default()
            .data(vk::DeviceOrHostAddressConstKHR { device_address: address })
            .stride(std::mem::size_of::<pointray_kernels::Aabb>() as u64);
        vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::AABBS)
            .geometry(vk::AccelerationStructureGeometryDataKHR { aabbs })
            .flags(vk::GeometryFlagsKHR::OPAQUE)
    };
    let range = |offset, count| {
        vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_offset(offset).primitive_count(count)
    };
    let (geometries, ranges) = match layout {
        BlasLayout::OneGeometry | BlasLayout::PatchGroups(_) => {
            (vec![geometry(aabbs)], vec![range(0, count)])
        }
        // Every geometry reads the same buffer from its own box on.
        BlasLayout::GeometryPerAabb => (0..count).map(|i| (geometry(aabbs), range(i * 24, 1))).unzip(),
    };
    BuildInput { ty: vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL, geometries, ranges }
}

/// A BLAS over an indexed triangle mesh (positions as vec4, 16-byte stride; u32 indices).
pub(crate) fn triangle_input<'a>(
    vertices: vk::DeviceAddress,
    vertex_count: u32,
    indices: vk::DeviceAddress,
    triangle_count: u32,
) -> BuildInput<'a> {
    let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
        .vertex_format(vk::Format::R32G32B32_SFLOAT)
        .vertex_data(vk::DeviceOrHostAddressConstKHR { device_address: vertices })
        .vertex_stride(16)
        .max_vertex(vertex_count.saturating_sub(1))
        .index_type(vk::IndexType::UINT32)
        .index_data(vk::DeviceOrHostAddressConstKHR { device_address: indices });
    let geometry = vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
        .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
        .flags(vk::GeometryFlagsKHR::OPAQUE);
    let range = vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(triangle_count);
    BuildInput {
        ty: vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
        geometries: vec![geometry],
        ranges: vec![range],
    }
}

/// A TLAS over `count` `VkAccelerationStructureInstanceKHR` records at `instances`.
pub(crate) fn instance_input<'a>(instances: vk::DeviceAddress, count: u32) -> BuildInput<'a> {
    let data = vk::AccelerationStructureGeometryInstancesDataKHR::default()
        .data(vk::DeviceOrHostAddressConstKHR { device_address: instances });
    let geometry = vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::INSTANCES)
        .geometry(vk::AccelerationStructureGeometryDataKHR { instances: data })
        .flags(vk::GeometryFlagsKHR::OPAQUE);
    let range = vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(count);
    BuildInput {
        ty: vk::AccelerationStructureTypeKHR::TOP_LEVEL,
        geometries: vec![geometry],
        ranges: vec![range],
    }
}

/// Builds for fast tracing; bottom levels are compacted when that saves enough memory.
pub(crate) fn build(
    context: &Arc<GpuContext>,
    input: &BuildInput<'_>,
) -> Result<AccelerationStructure, VulkanError> {
    let started = Instant::now();
    let compact = input.ty == vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL;
    let mut build_info = build_info(input, build_flags(input.ty));
    let sizes = sizes_of(context, &build_info, input);
    let structure = create(context, input.ty, sizes.acceleration_structure_size)?;
    let alignment = context.scratch_alignment;
    let scratch_bytes = sizes.build_scratch_size + alignment;
    let scratch = Buffer::new(
        context,
        "acceleration-structure scratch",
        scratch_bytes,
        addressable(vk::BufferUsageFlags::STORAGE_BUFFER),
        MemoryLocation::GpuOnly,
    )?;
    let scratch_address = scratch.device_address().next_multiple_of(alignment);
    build_info = build_info
        .dst_acceleration_structure(structure.handle)
        .scratch_data(vk::DeviceOrHostAddressKHR { device_address: scratch_address });
    let queries = compact.then(|| QueryPool::new(context)).transpose()?;
    context.submit_and_wait("building an acceleration structure", |command| {
        // SAFETY: every buffer the build reads or writes is alive until the wait returns.
        unsafe {
            context.acceleration.cmd_build_acceleration_structures(command, &[build_info], &[&input.ranges]);
            if let Some(queries) = &queries {
                queries.record_compacted_size(context, command, structure.handle);
            }
        }
    })?;
    // The compacted copy needs room; the scratch is done with.
    drop(scratch);
    let mut structure = match queries {
        Some(queries) => compact_if_it_pays(context, structure, queries.compacted_size(context)?)?,
        None => structure,
    };
    structure.build_time = started.elapsed();
    structure.build_bytes = build_peak(0, sizes.acceleration_structure_size, scratch_bytes);
    Ok(structure)
}

/// The most one build holds: its input and structure, with the scratch while building or a
/// compacted copy (smaller than the structure) while compacting.
pub(crate) fn build_peak(input: u64, structure: u64, scratch: u64) -> u64 {
    input + structure + scratch.max(structure)
}

/// Fast tracing; bottom levels may be compacted.
fn build_flags(ty: vk::AccelerationStructureTypeKHR) -> vk::BuildAccelerationStructureFlagsKHR {
    let fast = vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE;
    if ty == vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL {
        fast | vk::BuildAccelerationStructureFlagsKHR::ALLOW_COMPACTION
    } else {
        fast
    }
}

fn build_info<'a>(
    input: &'a BuildInput<'a>,
    flags: vk::BuildAccelerationStructureFlagsKHR,
) -> vk::AccelerationStructureBuildGeometryInfoKHR<'a> {
    vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(input.ty)
        .flags(flags)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(&input.geometries)
}

fn sizes_of(
    context: &GpuContext,
    build_info: &vk::AccelerationStructureBuildGeometryInfoKHR<'_>,
    input: &BuildInput<'_>,
) -> vk::AccelerationStructureBuildSizesInfoKHR<'static> {
    let counts: Vec<u32> = input.ranges.iter().map(|r| r.primitive_count).collect();
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: `build_info` describes `counts.len()` geometries; the query reads no addresses.
    unsafe {
        context.acceleration.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            build_info,
            &counts,
            &mut sizes,
        )
    };
    sizes
}

/// What building `input` takes on this device, before anything is uploaded (the query
/// ignores the input's addresses): the structure's size before compaction and the scratch.
pub(crate) fn build_sizes(context: &GpuContext, input: &BuildInput<'_>) -> (u64, u64) {
    let sizes = sizes_of(context, &build_info(input, build_flags(input.ty)), input);
    (sizes.acceleration_structure_size, sizes.build_scratch_size + context.scratch_alignment)
}

fn create(
    context: &Arc<GpuContext>,
    ty: vk::AccelerationStructureTypeKHR,
    size: u64,
) -> Result<AccelerationStructure, VulkanError> {
    let storage = Buffer::new(
        context,
        "acceleration structure",
        size,
        addressable(vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR),
        MemoryLocation::GpuOnly,
    )?;
    let info = vk::AccelerationStructureCreateInfoKHR::default().buffer(storage.handle).size(size).ty(ty);
    // SAFETY: `storage` is at least `size` bytes and outlives the structure (same owner).
    let handle = unsafe { context.acceleration.create_acceleration_structure(&info, None) }
        .during("creating an acceleration structure")?;
    let address_info =
        vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(handle);
    // SAFETY: `handle` was just created.
    let address = unsafe { context.acceleration.get_acceleration_structure_device_address(&address_info) };
    Ok(AccelerationStructure {
        context: context.clone(),
        handle,
        address,
        build_time: Duration::ZERO,
        build_bytes: 0,
        _storage: storage,
    })
}

fn compact_if_it_pays(
    context: &Arc<GpuContext>,
    built: AccelerationStructure,
    compacted_size: u64,
) -> Result<AccelerationStructure, VulkanError> {
    let built_size = built._storage.size;
    if compacted_size == 0 || (compacted_size as f64) > (built_size as f64) * (1.0 - COMPACTION_MIN_SAVING) {
        return Ok(built);
    }
    let compacted = create(context, vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL, compacted_size)?;
    tracing::debug!(built_size, compacted_size, "compacting a BLAS");
    context.submit_and_wait("compacting an acceleration structure", |command| {
        let copy = vk::CopyAccelerationStructureInfoKHR::default()
            .src(built.handle)
            .dst(compacted.handle)
            .mode(vk::CopyAccelerationStructureModeKHR::COMPACT);
        // SAFETY: both structures are alive until the wait returns.
        unsafe { context.acceleration.cmd_copy_acceleration_structure(command, &copy) };
    })?;
    Ok(compacted)
}

/// One compacted-size query.
struct QueryPool {
    context: Arc<GpuContext>,
    handle: vk::QueryPool,
}

impl QueryPool {
    fn new(context: &Arc<GpuContext>) -> Result<Self, VulkanError> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR)
            .query_count(1);
        // SAFETY: the device is alive; the pool is destroyed in Drop.
        let handle =
            unsafe { context.device.create_query_pool(&info, None) }.during("creating a query pool")?;
        Ok(Self { context: context.clone(), handle })
    }

    /// Records, after a build, the wait for it and the compacted-size query.
    unsafe fn record_compacted_size(
        &self,
        context: &GpuContext,
        command: vk::CommandBuffer,
        structure: vk::AccelerationStructureKHR,
    ) {
        let stage = vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR;
        // SAFETY: the caller records into a command buffer in the recording state.
        unsafe {
            context.device.cmd_reset_query_pool(command, self.handle, 0, 1);
            record_memory_barrier(
                &context.device,
                command,
                (stage, vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR),
                (stage, vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR),
            );
            context.acceleration.cmd_write_acceleration_structures_properties(
                command,
                &[structure],
                vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                self.handle,
                0,
            );
        }
    }

    fn compacted_size(&self, context: &GpuContext) -> Result<u64, VulkanError> {
        let mut size = [0u64];
        // SAFETY: the query was written by a submission that has completed.
        unsafe {
            context.device.get_query_pool_results(
                self.handle,
                0,
                &mut size,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .during("reading the compacted size")?;
        Ok(size[0])
    }
}

impl Drop for QueryPool {
    fn drop(&mut self) {
        // SAFETY: the pool's only use has completed.
        unsafe { self.context.device.destroy_query_pool(self.handle, None) };
    }
}
