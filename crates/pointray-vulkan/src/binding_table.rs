//! The shader binding table, laid out by the device's handle size and alignments.

use std::sync::Arc;

use ash::vk;

use crate::buffer::{Buffer, addressable};
use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::pipeline::{
    GROUP_HIT_FIRST, GROUP_MISS_FIRST, GROUP_RAYGEN, HIT_GROUP_COUNT, MISS_GROUP_COUNT, RayTracingPipeline,
};

pub(crate) struct ShaderBindingTable {
    _buffer: Buffer,
    pub(crate) raygen: vk::StridedDeviceAddressRegionKHR,
    pub(crate) miss: vk::StridedDeviceAddressRegionKHR,
    pub(crate) hit: vk::StridedDeviceAddressRegionKHR,
    pub(crate) callable: vk::StridedDeviceAddressRegionKHR,
}

/// Where each region sits in the table, relative to its (base-aligned) start.
#[derive(Debug, PartialEq, Eq)]
struct Layout {
    record_stride: u64,
    raygen_size: u64,
    miss_offset: u64,
    miss_size: u64,
    hit_offset: u64,
    hit_size: u64,
}

impl Layout {
    fn new(handle_size: u64, handle_alignment: u64, base_alignment: u64) -> Self {
        let record_stride = handle_size.next_multiple_of(handle_alignment);
        // Ray generation's stride must equal its size.
        let raygen_size = record_stride.next_multiple_of(base_alignment);
        let miss_size = (record_stride * u64::from(MISS_GROUP_COUNT)).next_multiple_of(base_alignment);
        let hit_size = (record_stride * u64::from(HIT_GROUP_COUNT)).next_multiple_of(base_alignment);
        Self {
            record_stride,
            raygen_size,
            miss_offset: raygen_size,
            miss_size,
            hit_offset: raygen_size + miss_size,
            hit_size,
        }
    }

    fn total(&self) -> u64 {
        self.hit_offset + self.hit_size
    }
}

impl ShaderBindingTable {
    pub(crate) fn new(context: &Arc<GpuContext>, pipeline: &RayTracingPipeline) -> Result<Self, VulkanError> {
        let properties = &context.ray_tracing_properties;
        let handle_size = u64::from(properties.shader_group_handle_size);
        let base_alignment = u64::from(properties.shader_group_base_alignment);
        let layout =
            Layout::new(handle_size, u64::from(properties.shader_group_handle_alignment), base_alignment);
        let group_count = GROUP_HIT_FIRST + HIT_GROUP_COUNT;
        // SAFETY: the pipeline has `group_count` groups.
        let handles = unsafe {
            context.ray_tracing.get_ray_tracing_shader_group_handles(
                pipeline.pipeline,
                0,
                group_count,
                (handle_size * u64::from(group_count)) as usize,
            )
        }
        .during("reading shader group handles")?;
        // The buffer's address need not be base-aligned: leave room to start at an aligned one.
        let mut bytes = vec![0u8; (layout.total() + base_alignment) as usize];
        let usage = addressable(vk::BufferUsageFlags::SHADER_BINDING_TABLE_KHR);
        let probe = Buffer::new(
            context,
            "shader binding table",
            bytes.len() as u64,
            usage,
            gpu_allocator::MemoryLocation::CpuToGpu,
        )?;
        let start = probe.device_address().next_multiple_of(base_alignment) - probe.device_address();
        let handle =
            |group: u32| &handles[(u64::from(group) * handle_size) as usize..][..handle_size as usize];
        let mut place = |offset: u64, group: u32| {
            let at = (start + offset) as usize;
            bytes[at..at + handle_size as usize].copy_from_slice(handle(group));
        };
        place(0, GROUP_RAYGEN);
        for i in 0..MISS_GROUP_COUNT {
            place(layout.miss_offset + u64::from(i) * layout.record_stride, GROUP_MISS_FIRST + i);
        }
        for i in 0..HIT_GROUP_COUNT {
            place(layout.hit_offset + u64::from(i) * layout.record_stride, GROUP_HIT_FIRST + i);
        }
        let mut buffer = probe;
        buffer.write(&bytes);
        let base = buffer.device_address() + start;
        let region = |offset: u64, stride: u64, size: u64| {
            vk::StridedDeviceAddressRegionKHR::default()
                .device_address(base + offset)
                .stride(stride)
                .size(size)
        };
        Ok(Self {
            raygen: region(0, layout.raygen_size, layout.raygen_size),
            miss: region(layout.miss_offset, layout.record_stride, layout.miss_size),
            hit: region(layout.hit_offset, layout.record_stride, layout.hit_size),
            callable: vk::StridedDeviceAddressRegionKHR::default(),
            _buffer: buffer,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_start_on_the_base_alignment() {
        // NVIDIA's values: 32-byte handles, 32-byte handle alignment, 64-byte base alignment.
        let layout = Layout::new(32, 32, 64);
        assert_eq!(layout.record_stride, 32);
        assert_eq!(layout.raygen_size, 64);
        assert_eq!((layout.miss_offset % 64, layout.hit_offset % 64), (0, 0));
        assert!(layout.miss_size >= 2 * 32 && layout.hit_size >= 3 * 32);
        // Three hit records of 32 bytes round up to two base alignments.
        assert_eq!(layout.total(), 64 + 64 + 128);
    }
}
