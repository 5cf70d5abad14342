//! A host-visible, coherent buffer the frame's bytes are written into before the copy.

use ash::vk;

use super::context::PresentContext;
use crate::error::ViewerError;

pub(crate) struct StagingBuffer {
    pub(crate) buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    mapped: *mut u8,
    pub(crate) size: u64,
}

impl StagingBuffer {
    pub(crate) fn new(context: &PresentContext, size: u64) -> Result<Self, ViewerError> {
        let device = &context.device;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(vk::BufferUsageFlags::TRANSFER_SRC)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: plain creation; on a later failure the buffer is destroyed before returning.
        let buffer =
            unsafe { device.create_buffer(&info, None) }.map_err(ViewerError::vk("vkCreateBuffer"))?;
        let bound = Self::bind_memory(context, buffer);
        match bound {
            Ok((memory, mapped)) => Ok(Self { buffer, memory, mapped, size }),
            Err(error) => {
                // SAFETY: the buffer is unused.
                unsafe { device.destroy_buffer(buffer, None) };
                Err(error)
            }
        }
    }

    fn bind_memory(
        context: &PresentContext,
        buffer: vk::Buffer,
    ) -> Result<(vk::DeviceMemory, *mut u8), ViewerError> {
        let device = &context.device;
        // SAFETY: the buffer is live.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let flags = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let memory_type = context
            .memory_type(requirements.memory_type_bits, flags)
            .ok_or_else(|| ViewerError::PresentSetup("no host-visible coherent memory for staging".into()))?;
        let allocate = vk::MemoryAllocateInfo::default()
            .allocation_size(requirements.size)
            .memory_type_index(memory_type);
        // SAFETY: allocation, binding and mapping of fresh objects; freed on failure.
        unsafe {
            let memory =
                device.allocate_memory(&allocate, None).map_err(ViewerError::vk("vkAllocateMemory"))?;
            let mapped = device
                .bind_buffer_memory(buffer, memory, 0)
                .and_then(|()| device.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()));
            match mapped {
                Ok(pointer) => Ok((memory, pointer.cast())),
                Err(result) => {
                    device.free_memory(memory, None);
                    Err(ViewerError::Present { what: "binding or mapping staging memory", result })
                }
            }
        }
    }

    /// The caller has waited for the last copy out of this buffer.
    pub(crate) fn write(&self, bytes: &[u8]) {
        assert!(bytes.len() as u64 <= self.size, "staging buffer too small");
        // SAFETY: the mapping covers `size` bytes and no copy is reading it (see above).
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), self.mapped, bytes.len()) };
    }

    pub(crate) fn destroy(&mut self, device: &ash::Device) {
        // SAFETY: the device is idle or the buffer's last copy has completed.
        unsafe {
            device.destroy_buffer(self.buffer, None);
            device.free_memory(self.memory, None);
        }
    }
}
