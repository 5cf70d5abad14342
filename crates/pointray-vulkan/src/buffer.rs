//! Buffers with gpu-allocator memory, and uploads through a bounded staging buffer.

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use rayon::prelude::*;

use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};

/// The most bytes an upload stages at once. A large point set's records (gigabytes) go up
/// in pieces through this much host memory, rather than through a staging copy of them all.
const STAGING_BYTES: u64 = 64 << 20;

/// The piece of a host write each core copies.
const WRITE_PIECE_BYTES: usize = 1 << 20;

/// A buffer and its memory, freed on drop.
pub(crate) struct Buffer {
    context: Arc<GpuContext>,
    pub(crate) handle: vk::Buffer,
    allocation: Option<Allocation>,
    pub(crate) size: u64,
}

/// The alignment of every buffer's start: what `patch_buffers.glsl` promises the driver.
const RECORD_ALIGNMENT: u64 = 16;

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
        let mut requirements = unsafe { device.get_buffer_memory_requirements(handle) };
        // The shaders declare record buffers 16-byte aligned (`buffer_reference_align`), which
        // lets the driver read a record in 128-bit loads; the device's own requirement may
        // be smaller.
        requirements.alignment = requirements.alignment.max(RECORD_ALIGNMENT);
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

    /// A device-local buffer holding `bytes`, copied through a staging buffer of at most
    /// `STAGING_BYTES`.
    pub(crate) fn device_with_data(
        context: &Arc<GpuContext>,
        name: &'static str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, VulkanError> {
        Self::device_from_pieces(context, name, bytes.len() as u64, usage, std::iter::once(bytes))
    }

    /// A device-local buffer of `size` bytes holding the records of `pieces` one after
    /// another, each piece made only as it goes up, so that contents made on the way are never
    /// held on the host whole.
    pub(crate) fn device_from_pieces<T: Pod>(
        context: &Arc<GpuContext>,
        name: &'static str,
        size: u64,
        usage: vk::BufferUsageFlags,
        pieces: impl Iterator<Item = impl AsRef<[T]>>,
    ) -> Result<Self, VulkanError> {
        let buffer = Self::new(
            context,
            name,
            size,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let mut offset = 0;
        for piece in pieces {
            let piece: &[u8] = bytemuck::cast_slice(piece.as_ref());
            buffer.fill(name, offset, piece, STAGING_BYTES)?;
            offset += piece.len() as u64;
        }
        Ok(buffer)
    }

    /// Copies `bytes` into this device-local buffer from `offset` on through a staging buffer
    /// of at most `staging_bytes`, one piece at a time.
    fn fill(
        &self,
        name: &'static str,
        offset: u64,
        bytes: &[u8],
        staging_bytes: u64,
    ) -> Result<(), VulkanError> {
        if bytes.is_empty() {
            return Ok(());
        }
        let context = &self.context;
        let piece_bytes = (bytes.len() as u64).min(staging_bytes.max(1));
        let mut staging = Self::new(
            context,
            "staging upload",
            piece_bytes,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        for (index, piece) in bytes.chunks(piece_bytes as usize).enumerate() {
            staging.write(piece);
            let region = vk::BufferCopy::default()
                .dst_offset(offset + index as u64 * piece_bytes)
                .size(piece.len() as u64);
            context.submit_and_wait(name, |command| {
                // SAFETY: both buffers are alive; the staging buffer holds the piece and this
                // buffer reaches past its offset, as `bytes` fits it.
                unsafe { context.device.cmd_copy_buffer(command, staging.handle, self.handle, &[region]) };
            })?;
        }
        Ok(())
    }

    /// Copies `bytes` into a host-visible buffer's start, on every core.
    pub(crate) fn write(&mut self, bytes: &[u8]) {
        if let Some(mapped) = self.allocation.as_mut().and_then(|a| a.mapped_slice_mut()) {
            mapped[..bytes.len()]
                .par_chunks_mut(WRITE_PIECE_BYTES)
                .zip(bytes.par_chunks(WRITE_PIECE_BYTES))
                .for_each(|(to, from)| to.copy_from_slice(from));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::twin_probe::probe_context;

    /// An upload larger than its staging buffer, in two parts, arrives whole and in order,
    /// without a validation message.
    #[test]
    fn an_upload_goes_up_in_pieces_and_arrives_whole() {
        let Some(context) = probe_context() else { return };
        let bytes: Vec<u8> = (0..10_007u32).map(|i| (i * 31 + i / 256) as u8).collect();
        let size = bytes.len() as u64;
        let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let device = Buffer::new(&context, "upload", size, usage, MemoryLocation::GpuOnly).unwrap();
        device.fill("upload", 0, &bytes[..4000], 1000).unwrap();
        device.fill("upload", 4000, &bytes[4000..], 1000).unwrap();
        let back = Buffer::new(&context, "read back", size, usage, MemoryLocation::GpuToCpu).unwrap();
        context
            .submit_and_wait("read back", |command| {
                let region = vk::BufferCopy::default().size(size);
                // SAFETY: both buffers are alive and `size` bytes long.
                unsafe { context.device.cmd_copy_buffer(command, device.handle, back.handle, &[region]) };
            })
            .unwrap();
        assert!(back.read()[..bytes.len()] == bytes[..], "the bytes read back differ");
        assert_eq!(context.message_counter().count(), 0, "validation messages (printed above)");
    }
}
