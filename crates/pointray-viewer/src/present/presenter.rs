//! Shows host pixels in the window: each frame is written into a host-visible staging buffer,
//! copied into the acquired swapchain image with `vkCmdCopyBufferToImage`, and presented.
//! One frame is in flight at a time; the CPU renderer's frames are on the host anyway.

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::ByteOrder;
use super::context::PresentContext;
use super::staging::StagingBuffer;
use crate::error::ViewerError;
use pointray_vulkan::validation::MessageCounter;
use pointray_vulkan::{Swapchain, record_copy_to_present_image};

pub struct Presenter {
    swapchain: Option<Swapchain>,
    staging: Option<StagingBuffer>,
    command_pool: vk::CommandPool,
    commands: vk::CommandBuffer,
    acquired: vk::Semaphore,
    in_flight: vk::Fence,
    window_size: (u32, u32),
    vsync: bool,
    stale: bool,
    context: PresentContext,
}

/// What `present` did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presented {
    Shown,
    /// The window is minimised or the swapchain had to be rebuilt; nothing was shown.
    Skipped,
}

impl Presenter {
    pub fn new(
        display: RawDisplayHandle,
        window: RawWindowHandle,
        window_size: (u32, u32),
        vsync: bool,
        validation: bool,
    ) -> Result<Self, ViewerError> {
        let context = PresentContext::new(display, window, validation)?;
        // A copy of the function table: `context` moves into the presenter below.
        let device = context.device.clone();
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(context.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: plain creations on the live device; on failure the context's drop cleans up
        // the device, and `Presenter::drop` the objects made so far (null handles are ignored).
        let mut presenter = Self {
            swapchain: None,
            staging: None,
            command_pool: vk::CommandPool::null(),
            commands: vk::CommandBuffer::null(),
            acquired: vk::Semaphore::null(),
            in_flight: vk::Fence::null(),
            window_size,
            vsync,
            stale: true,
            context,
        };
        unsafe {
            presenter.command_pool = device
                .create_command_pool(&pool_info, None)
                .map_err(ViewerError::vk("vkCreateCommandPool"))?;
            let allocate = vk::CommandBufferAllocateInfo::default()
                .command_pool(presenter.command_pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            presenter.commands = device
                .allocate_command_buffers(&allocate)
                .map_err(ViewerError::vk("vkAllocateCommandBuffers"))?[0];
            presenter.acquired = device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                .map_err(ViewerError::vk("vkCreateSemaphore"))?;
            let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            presenter.in_flight =
                device.create_fence(&signalled, None).map_err(ViewerError::vk("vkCreateFence"))?;
        }
        Ok(presenter)
    }

    /// The window's new size; the swapchain is rebuilt before the next frame.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.window_size = (width, height);
        self.stale = true;
    }

    pub fn set_vsync(&mut self, vsync: bool) {
        self.vsync = vsync;
        self.stale = true;
    }

    pub fn vsync(&self) -> bool {
        self.vsync
    }

    /// The size `present` wants its pixels in (after `prepare`), and their byte order.
    pub fn target(&mut self) -> Result<Option<(vk::Extent2D, ByteOrder)>, ViewerError> {
        self.ensure_swapchain()?;
        Ok(self.swapchain.as_ref().map(|s| (s.extent(), ByteOrder::from(s.output()))))
    }

    /// Validation messages of the presentation context; still counting during teardown.
    pub fn message_counter(&self) -> std::sync::Arc<MessageCounter> {
        self.context.instance.message_counter()
    }

    /// Shows `pixels` (4 bytes each, in `target()`'s size and byte order).
    pub fn present(&mut self, pixels: &[u8]) -> Result<Presented, ViewerError> {
        self.ensure_swapchain()?;
        let Some(swapchain) = &self.swapchain else { return Ok(Presented::Skipped) };
        let extent = swapchain.extent();
        let expected = extent.width as usize * extent.height as usize * 4;
        if pixels.len() != expected {
            return Err(ViewerError::PresentSetup(format!(
                "a frame of {} bytes does not fit the {}x{} swapchain",
                pixels.len(),
                extent.width,
                extent.height
            )));
        }
        let device = &self.context.device;
        // SAFETY: the fence belongs to this device; waiting makes the staging buffer and
        // command buffer free to reuse.
        unsafe { device.wait_for_fences(&[self.in_flight], true, u64::MAX) }
            .map_err(ViewerError::vk("vkWaitForFences"))?;
        // SAFETY: the semaphore is unsignalled (its last wait completed with the fence).
        let acquired = unsafe {
            let swapchain_fn = &self.context.swapchain_fn;
            swapchain_fn.acquire_next_image(swapchain.handle(), u64::MAX, self.acquired, vk::Fence::null())
        };
        let index = match acquired {
            Ok((index, _suboptimal)) => index,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                return Ok(Presented::Skipped);
            }
            Err(result) => return Err(ViewerError::Present { what: "vkAcquireNextImageKHR", result }),
        };
        let staging = match self.staging.take() {
            Some(staging) if staging.size >= pixels.len() as u64 => staging,
            old => {
                if let Some(mut old) = old {
                    old.destroy(device);
                }
                StagingBuffer::new(&self.context, pixels.len() as u64)?
            }
        };
        staging.write(pixels);
        let buffer = staging.buffer;
        self.staging = Some(staging);
        let swapchain = self.swapchain.as_ref().expect("checked above");
        self.submit_copy(swapchain, buffer, index)?;
        let (swapchains, indices, waits) = ([swapchain.handle()], [index], [swapchain.rendered(index)]);
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and its copy submitted, signalling `waits`.
        match unsafe { self.context.swapchain_fn.queue_present(self.context.queue, &info) } {
            Ok(false) => Ok(Presented::Shown),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                Ok(Presented::Shown)
            }
            Err(result) => Err(ViewerError::Present { what: "vkQueuePresentKHR", result }),
        }
    }

    fn submit_copy(&self, swapchain: &Swapchain, buffer: vk::Buffer, index: u32) -> Result<(), ViewerError> {
        let device = &self.context.device;
        let image = swapchain.image(index);
        // SAFETY: the fence wait above made the command buffer idle; it is re-recorded whole.
        unsafe {
            device.reset_fences(&[self.in_flight]).map_err(ViewerError::vk("vkResetFences"))?;
            device
                .reset_command_buffer(self.commands, vk::CommandBufferResetFlags::empty())
                .map_err(ViewerError::vk("vkResetCommandBuffer"))?;
            let begin =
                vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(self.commands, &begin)
                .map_err(ViewerError::vk("vkBeginCommandBuffer"))?;
            record_copy_to_present_image(device, self.commands, buffer, image, swapchain.extent());
            device.end_command_buffer(self.commands).map_err(ViewerError::vk("vkEndCommandBuffer"))?;
            let (waits, stages) = ([self.acquired], [vk::PipelineStageFlags::TRANSFER]);
            let (commands, signals) = ([self.commands], [swapchain.rendered(index)]);
            let submit = vk::SubmitInfo::default()
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages)
                .command_buffers(&commands)
                .signal_semaphores(&signals);
            device
                .queue_submit(self.context.queue, &[submit], self.in_flight)
                .map_err(ViewerError::vk("vkQueueSubmit"))
        }
    }

    /// Rebuilds the swapchain when the window changed; none while the window has no area.
    fn ensure_swapchain(&mut self) -> Result<(), ViewerError> {
        if !self.stale {
            return Ok(());
        }
        self.wait_idle()?;
        let on = self.context.swapchain_device();
        if let Some(mut old) = self.swapchain.take() {
            // SAFETY: made with `on`; the device is idle.
            unsafe { old.destroy(on) };
        }
        if self.window_size.0 > 0 && self.window_size.1 > 0 {
            // SAFETY: the context's live device, surface and loaders; the old swapchain was
            // destroyed above.
            let made = unsafe { Swapchain::new(on, self.window_size, self.vsync) };
            self.swapchain = made.map_err(ViewerError::from_swapchain)?;
        }
        self.stale = false;
        Ok(())
    }

    fn wait_idle(&self) -> Result<(), ViewerError> {
        // SAFETY: the device is live.
        unsafe { self.context.device.device_wait_idle() }.map_err(ViewerError::vk("vkDeviceWaitIdle"))
    }
}

impl Drop for Presenter {
    fn drop(&mut self) {
        // Best effort: if the device is lost there is nothing left to wait for.
        let _ = self.wait_idle();
        let device = &self.context.device;
        if let Some(mut swapchain) = self.swapchain.take() {
            // SAFETY: made with the context's device and surface; the device is idle (or lost).
            unsafe { swapchain.destroy(self.context.swapchain_device()) };
        }
        if let Some(mut staging) = self.staging.take() {
            staging.destroy(device);
        }
        // SAFETY: the device is idle; destroying null handles is allowed.
        unsafe {
            device.destroy_fence(self.in_flight, None);
            device.destroy_semaphore(self.acquired, None);
            device.destroy_command_pool(self.command_pool, None);
        }
    }
}
