//! Buffers with gpu-allocator memory, and uploads through a staging buffer.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};

use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};

/// A buffer and its memory, freed on drop.
pub(crate) struct Buffer {
    context: Arc<GpuContext>,
    pub(crate) handle: vk::Buffer,
    allocation: Option<Allocation>,
    pub(crate) size: u64,
}

impl Buffer {
    /// A buffer of `size` bytes (at least 1) at `location`, with `usage`.
    pub(crate) fn new(
        context: &Arc<GpuContext>,
        name: &'static str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self, VulkanError> {
        let size = size.max(1);
        let info =
            vk::BufferCreateInfo::default().size(size).usage(usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        let device = &context.device;
        // SAFETY: the device is alive; the buffer is destroyed in Drop.
        let handle = unsafe { device.create_buffer(&info, None) }.during(name)?;
        // SAFETY: `handle` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(handle) };
        let allocation = context
            .allocator
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| VulkanError::from_allocation(name, e));
        let mut buffer = Self { context: context.clone(), handle, allocation: None, size };
        let allocation = allocation?;
        // SAFETY: the allocation satisfies `requirements` and is not bound elsewhere.
        unsafe { device.bind_buffer_memory(handle, allocation.memory(), allocation.offset()) }
            .during(name)?;
        buffer.allocation = Some(allocation);
        Ok(buffer)
    }

    /// A host-visible buffer holding `bytes`.
    pub(crate) fn host_with_data(
        context: &Arc<GpuContext>,
        name: &'static str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, VulkanError> {
        let mut buffer = Self::new(context, name, bytes.len() as u64, usage, MemoryLocation::CpuToGpu)?;
        buffer.write(bytes);
        Ok(buffer)
    }

    /// A device-local buffer holding `bytes`, copied through a staging buffer.
    pub(crate) fn device_with_data(
        context: &Arc<GpuContext>,
        name: &'static str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, VulkanError> {
        let size = bytes.len() as u64;
        let buffer = Self::new(
            context,
            name,
            size,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        if bytes.is_empty() {
            return Ok(buffer);
        }
        let staging =
            Self::host_with_data(context, "staging upload", bytes, vk::BufferUsageFlags::TRANSFER_SRC)?;
        context.submit_and_wait(name, |command| {
            let region = vk::BufferCopy::default().size(size);
            // SAFETY: both buffers are alive and at least `size` bytes.
            unsafe { context.device.cmd_copy_buffer(command, staging.handle, buffer.handle, &[region]) };
        })?;
        Ok(buffer)
    }

    /// Copies `bytes` into a host-visible buffer's start.
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        if let Some(mapped) = self.allocation.as_mut().and_then(|a| a.mapped_slice_mut()) {
            mapped[..bytes.len()].copy_from_slice(bytes);
        }
    }

    /// The contents of a host-visible buffer.
    pub(crate) fn read(&self) -> &[u8] {
        let mapped = self.allocation.as_ref().and_then(|a| a.mapped_slice()).unwrap_or(&[]);
        &mapped[..mapped.len().min(self.size as usize)]
    }

    pub(crate) fn device_address(&self) -> vk::DeviceAddress {
        let info = vk::BufferDeviceAddressInfo::default().buffer(self.handle);
        // SAFETY: every buffer that asks for its address was made with SHADER_DEVICE_ADDRESS.
        unsafe { self.context.device.get_buffer_device_address(&info) }
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: callers keep buffers alive until the GPU work using them has finished.
        unsafe { self.context.device.destroy_buffer(self.handle, None) };
        if let Some(allocation) = self.allocation.take() {
            let mut allocator =
                self.context.allocator.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            let _ = allocator.free(allocation);
        }
    }
}

/// Usage of a buffer that shaders or acceleration-structure builds read by address.
pub(crate) fn addressable(usage: vk::BufferUsageFlags) -> vk::BufferUsageFlags {
    usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS
}

/// Usage of a buffer that shaders read by address.
pub(crate) fn storage_usage() -> vk::BufferUsageFlags {
    addressable(vk::BufferUsageFlags::STORAGE_BUFFER)
}

/// Usage of a buffer that acceleration-structure builds read (and shaders may too).
pub(crate) fn build_input_usage() -> vk::BufferUsageFlags {
    addressable(
        vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
            | vk::BufferUsageFlags::STORAGE_BUFFER,
    )
}
