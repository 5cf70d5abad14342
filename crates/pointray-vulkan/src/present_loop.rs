//! A window's frame loop, one frame in flight: acquire, record and submit, present, and
//! rebuild the swapchain after a change. Shared by `WindowTarget` and the viewer's host-copy
//! presenter.

use ash::vk;

use crate::error::{VkContext, VulkanError};
use crate::swapchain::{Swapchain, SwapchainDevice};

/// What `present` did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presented {
    Shown,
    /// The window has no area or its swapchain had to be rebuilt; nothing was shown.
    Skipped,
}

/// A window's frames, one in flight at a time: the swapchain, rebuilt before the next frame
/// once the window changed size or vsync or the surface reported it out of date, and the
/// command buffer, semaphore and fence of the frame. Not destroyed on drop (the surface's
/// owner orders the teardown): call `destroy` before destroying the surface.
pub struct PresentLoop {
    swapchain: Option<Swapchain>,
    command_pool: vk::CommandPool,
    commands: vk::CommandBuffer,
    acquired: vk::Semaphore,
    in_flight: vk::Fence,
    window_size: (u32, u32),
    vsync: bool,
    stale: bool,
    on: SwapchainDevice,
}

impl PresentLoop {
    /// Presenting with FIFO (`vsync`) or mailbox/immediate; the swapchain is made before the
    /// first frame.
    ///
    /// # Safety
    /// Every handle in `on` is live until `destroy` and they belong together (as for
    /// `Swapchain::new`); the surface has no other swapchain.
    pub unsafe fn new(
        on: SwapchainDevice,
        window_size: (u32, u32),
        vsync: bool,
    ) -> Result<Self, VulkanError> {
        let mut frames = Self {
            swapchain: None,
            command_pool: vk::CommandPool::null(),
            commands: vk::CommandBuffer::null(),
            acquired: vk::Semaphore::null(),
            in_flight: vk::Fence::null(),
            window_size,
            vsync,
            stale: true,
            on,
        };
        if let Err(error) = frames.create_frame_objects() {
            frames.destroy();
            return Err(error);
        }
        Ok(frames)
    }

    fn create_frame_objects(&mut self) -> Result<(), VulkanError> {
        let device = &self.on.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.on.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: plain creations on the live device, destroyed in `destroy`.
        unsafe {
            self.command_pool =
                device.create_command_pool(&pool_info, None).during("creating the window's command pool")?;
            let allocate = vk::CommandBufferAllocateInfo::default()
                .command_pool(self.command_pool)
                .level(vk::CommandBufferLevel::PRIMARY)
                .command_buffer_count(1);
            self.commands =
                device.allocate_command_buffers(&allocate).during("allocating the window's commands")?[0];
            self.acquired = device
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
                .during("creating the acquire semaphore")?;
            let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            self.in_flight = device.create_fence(&signalled, None).during("creating the frame fence")?;
        }
        Ok(())
    }

    /// The window's new size; the swapchain follows before the next frame.
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

    /// The current swapchain (after `ensure_swapchain`); `None` while the window has no area.
    pub fn swapchain(&self) -> Option<&Swapchain> {
        self.swapchain.as_ref()
    }

    /// Rebuilds the swapchain when the window changed (waiting for the device first); `true`
    /// when it did, which ends whatever the old images held.
    pub fn ensure_swapchain(&mut self) -> Result<bool, VulkanError> {
        if !self.stale {
            return Ok(false);
        }
        // SAFETY: the device is live; waiting makes every swapchain object idle.
        unsafe { self.on.device.device_wait_idle() }.during("waiting before a swapchain rebuild")?;
        if let Some(mut old) = self.swapchain.take() {
            // SAFETY: made with `on`; the device is idle.
            unsafe { old.destroy(&self.on) };
        }
        if self.window_size.0 > 0 && self.window_size.1 > 0 {
            // SAFETY: `new`'s contract; the old swapchain was destroyed above.
            self.swapchain = unsafe { Swapchain::new(&self.on, self.window_size, self.vsync) }?;
        }
        self.stale = false;
        Ok(true)
    }

    /// Waits until the last submitted frame is done.
    pub fn wait_for_last_frame(&self) -> Result<(), VulkanError> {
        // SAFETY: the fence belongs to this device.
        unsafe { self.on.device.wait_for_fences(&[self.in_flight], true, u64::MAX) }
            .during("waiting for the last frame")
    }

    /// The index of the next image, once the last frame is done; `None` when there is no
    /// swapchain or it is out of date (it is rebuilt before the next frame).
    pub fn acquire(&mut self) -> Result<Option<u32>, VulkanError> {
        let Some(swapchain) = &self.swapchain else { return Ok(None) };
        self.wait_for_last_frame()?;
        // SAFETY: the fence wait above: no earlier frame still waits on `acquired`.
        let acquired = unsafe {
            self.on.swapchain_fn.acquire_next_image(
                swapchain.handle(),
                u64::MAX,
                self.acquired,
                vk::Fence::null(),
            )
        };
        match acquired {
            Ok((index, suboptimal)) => {
                self.stale |= suboptimal;
                Ok(Some(index))
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                Ok(None)
            }
            Err(result) => Err(VulkanError::from_vk("acquiring a swapchain image", result)),
        }
    }

    /// Records the frame for image `index` (from `acquire`) with `record` and submits it: it
    /// starts once the image is acquired (at the transfer stage) and signals the image's
    /// present semaphore and the frame fence.
    ///
    /// # Safety
    /// `record` records valid commands into the command buffer it is given (which is
    /// recording, on this loop's device), using only resources that live until the frame is
    /// done (`wait_for_last_frame`).
    pub unsafe fn submit(
        &self,
        index: u32,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<(), VulkanError> {
        let Some(swapchain) = &self.swapchain else {
            return Err(VulkanError::InvalidSettings("a frame was submitted without a swapchain".into()));
        };
        let (device, command) = (&self.on.device, self.commands);
        // SAFETY: `acquire` waited for the last frame, so the command buffer and fence are idle;
        // the buffer is re-recorded whole; the caller's contract covers what `record` adds.
        unsafe {
            device.reset_fences(&[self.in_flight]).during("resetting the frame fence")?;
            device
                .reset_command_buffer(command, vk::CommandBufferResetFlags::empty())
                .during("resetting the window's commands")?;
            let begin =
                vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(command, &begin).during("recording a window frame")?;
            record(device, command);
            device.end_command_buffer(command).during("recording a window frame")?;
            let (waits, stages) = ([self.acquired], [vk::PipelineStageFlags::TRANSFER]);
            let (commands, signals) = ([command], [swapchain.rendered(index)]);
            let submit = vk::SubmitInfo::default()
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages)
                .command_buffers(&commands)
                .signal_semaphores(&signals);
            device.queue_submit(self.on.queue, &[submit], self.in_flight).during("submitting a window frame")
        }
    }

    /// Presents image `index` once its submitted frame is done.
    pub fn present(&mut self, index: u32) -> Result<Presented, VulkanError> {
        let Some(swapchain) = &self.swapchain else { return Ok(Presented::Skipped) };
        let (swapchains, indices, waits) = ([swapchain.handle()], [index], [swapchain.rendered(index)]);
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and its frame submitted, signalling `waits`.
        match unsafe { self.on.swapchain_fn.queue_present(self.on.queue, &info) } {
            Ok(false) => Ok(Presented::Shown),
            // The image was still presented (suboptimal) or the present is dropped (out of
            // date); either way the swapchain is rebuilt before the next frame.
            Ok(true) => {
                self.stale = true;
                Ok(Presented::Shown)
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                Ok(Presented::Skipped)
            }
            Err(result) => Err(VulkanError::from_vk("presenting a swapchain image", result)),
        }
    }

    /// The handles this loop presents with.
    pub fn device(&self) -> &SwapchainDevice {
        &self.on
    }

    /// Waits for the device, then destroys the swapchain and the frame's objects (not the
    /// surface). Calling it again does nothing.
    pub fn destroy(&mut self) {
        let device = &self.on.device;
        // SAFETY: after the wait nothing uses these objects; null handles are ignored, and
        // each is nulled so that a second call destroys nothing.
        unsafe {
            // Best effort: if the device is lost there is nothing left to wait for.
            let _ = device.device_wait_idle();
            if let Some(mut swapchain) = self.swapchain.take() {
                swapchain.destroy(&self.on);
            }
            device.destroy_fence(std::mem::take(&mut self.in_flight), None);
            device.destroy_semaphore(std::mem::take(&mut self.acquired), None);
            device.destroy_command_pool(std::mem::take(&mut self.command_pool), None);
        }
        self.commands = vk::CommandBuffer::null();
    }
}
