//! A trace's descriptor set, in a pool of its own, with the frame uniforms it binds: the
//! scene's top level, uniforms and object records, and the storage buffers the trace's ray
//! generation reads and writes. Frames (`TraceTarget`) and ray lists (`RayListTarget`) each
//! hold one.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::buffer::Buffer;
use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::gpu_records::FrameUniforms;
use crate::pipeline::{BINDING_FRAME, BINDING_OBJECTS, BINDING_TLAS, RayTracingPipeline};
use crate::prepared_scene::PreparedScene;

pub(crate) struct TraceDescriptors {
    context: Arc<GpuContext>,
    pool: vk::DescriptorPool,
    pub(crate) set: vk::DescriptorSet,
    uniforms: Buffer,
}

/// A storage binding's buffer, or the bytes `offset .. offset + range` of it.
pub(crate) struct StorageRange<'a> {
    pub(crate) binding: u32,
    pub(crate) buffer: &'a Buffer,
    pub(crate) offset: u64,
    pub(crate) range: u64,
}

impl<'a> StorageRange<'a> {
    pub(crate) fn whole(binding: u32, buffer: &'a Buffer) -> Self {
        Self { binding, buffer, offset: 0, range: vk::WHOLE_SIZE }
    }
}

impl TraceDescriptors {
    pub(crate) fn new(context: &Arc<GpuContext>, pipeline: &RayTracingPipeline) -> Result<Self, VulkanError> {
        let sizes = [
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                .descriptor_count(1),
            vk::DescriptorPoolSize::default().ty(vk::DescriptorType::UNIFORM_BUFFER).descriptor_count(1),
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(pipeline.storage_binding_count()),
        ];
        let pool_info = vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes);
        let device = &context.device;
        // SAFETY: the device is alive; the pool is destroyed in Drop.
        let pool = unsafe { device.create_descriptor_pool(&pool_info, None) }
            .during("creating a descriptor pool")?;
        let uniforms = Buffer::new(
            context,
            "frame uniforms",
            std::mem::size_of::<FrameUniforms>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        );
        let uniforms = match uniforms {
            Ok(uniforms) => uniforms,
            Err(error) => {
                // SAFETY: nothing uses the new pool.
                unsafe { device.destroy_descriptor_pool(pool, None) };
                return Err(error);
            }
        };
        let mut owned = Self { context: context.clone(), pool, set: vk::DescriptorSet::null(), uniforms };
        let layouts = [pipeline.set_layout];
        let allocate = vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts);
        // SAFETY: the pool has room for exactly this set.
        let sets =
            unsafe { device.allocate_descriptor_sets(&allocate) }.during("allocating a descriptor set")?;
        owned.set = sets[0];
        Ok(owned)
    }

    /// Points the set at `scene`'s top level and objects, writes its camera and lights to the
    /// uniforms, and points it at each of `storage`. No submitted trace may still use the set.
    pub(crate) fn write(&mut self, scene: &PreparedScene, storage: &[StorageRange]) {
        self.uniforms.write(bytemuck::bytes_of(&scene.frame_uniforms()));
        let structures = [scene.tlas.handle];
        let mut tlas =
            vk::WriteDescriptorSetAccelerationStructureKHR::default().acceleration_structures(&structures);
        let info = |buffer: &Buffer, offset, range| {
            [vk::DescriptorBufferInfo::default().buffer(buffer.handle).offset(offset).range(range)]
        };
        let uniform_info = info(&self.uniforms, 0, vk::WHOLE_SIZE);
        let object_info = info(&scene.objects, 0, vk::WHOLE_SIZE);
        let storage_infos: Vec<_> = storage.iter().map(|s| info(s.buffer, s.offset, s.range)).collect();
        let write = |binding, ty| {
            vk::WriteDescriptorSet::default().dst_set(self.set).dst_binding(binding).descriptor_type(ty)
        };
        let storage_type = vk::DescriptorType::STORAGE_BUFFER;
        let mut writes = vec![
            write(BINDING_TLAS, vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                .descriptor_count(1)
                .push_next(&mut tlas),
            write(BINDING_FRAME, vk::DescriptorType::UNIFORM_BUFFER).buffer_info(&uniform_info),
            write(BINDING_OBJECTS, storage_type).buffer_info(&object_info),
        ];
        writes.extend(
            storage
                .iter()
                .zip(&storage_infos)
                .map(|(s, info)| write(s.binding, storage_type).buffer_info(info)),
        );
        // SAFETY: every written resource is alive; the caller's contract says the set is idle.
        unsafe { self.context.device.update_descriptor_sets(&writes, &[]) };
    }
}

impl Drop for TraceDescriptors {
    fn drop(&mut self) {
        // SAFETY: every trace using the set was waited on; the set goes with its pool.
        unsafe { self.context.device.destroy_descriptor_pool(self.pool, None) };
    }
}
