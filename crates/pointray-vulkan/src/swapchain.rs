//! A window's swapchain: images that display pixels are copied into, recreated when the
//! window changes size or the surface reports it out of date.
//!
//! Built from raw handles rather than the renderer's context, so that a presenter with its own
//! device (the viewer's host-copy path, for machines whose GPU cannot ray trace) shares it
//! with `WindowTarget`: the swapchain, the copy into its images and the frame loop around them
//! (`PresentLoop`: acquire, record and submit, present, rebuild after a change).

use ash::vk;

use crate::error::{VkContext, VulkanError};
use crate::surface_choice::{pick_composite_alpha, pick_extent, pick_format, pick_present_mode};
use crate::trace_target::PixelOutput;

/// The device, queue, surface and loaders a window's frames are presented with. The owner
/// of these handles keeps them alive while anything made with them lives.
#[derive(Clone)]
pub struct SwapchainDevice {
    pub device: ash::Device,
    pub physical: vk::PhysicalDevice,
    /// A queue of `queue_family` that can present to the surface and copy.
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub surface: vk::SurfaceKHR,
    pub surface_fn: ash::khr::surface::Instance,
    pub swapchain_fn: ash::khr::swapchain::Device,
    /// Names the device in errors.
    pub device_name: String,
}

/// A swapchain whose images are filled by copies (`TRANSFER_DST`), with one present
/// semaphore per image. Not destroyed on drop: call `destroy` with the same device.
pub struct Swapchain {
    handle: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    extent: vk::Extent2D,
    output: PixelOutput,
    /// One per image: signalled when the frame for that image is done, waited on by present.
    /// Per image because a present's semaphore may be reused only once its image comes back.
    rendered: Vec<vk::Semaphore>,
}

impl Swapchain {
    /// `window_size` is used when the surface leaves the extent to the application; `None`
    /// while the window has no area (minimised).
    ///
    /// # Safety
    /// Every handle in `on` is live and they belong together (the loaders were made from the
    /// device's instance and device, the surface from that instance); the surface has no
    /// other swapchain.
    pub unsafe fn new(
        on: &SwapchainDevice,
        window_size: (u32, u32),
        vsync: bool,
    ) -> Result<Option<Self>, VulkanError> {
        let (physical, surface, surface_fn) = (on.physical, on.surface, &on.surface_fn);
        // SAFETY: plain queries on the live surface (the caller's contract).
        let (capabilities, formats, modes) = unsafe {
            (
                surface_fn
                    .get_physical_device_surface_capabilities(physical, surface)
                    .during("querying the surface's capabilities")?,
                surface_fn
                    .get_physical_device_surface_formats(physical, surface)
                    .during("querying the surface's formats")?,
                surface_fn
                    .get_physical_device_surface_present_modes(physical, surface)
                    .during("querying the surface's present modes")?,
            )
        };
        if !capabilities.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_DST) {
            return Err(VulkanError::NoSuitableDevice(format!(
                "the window's images on {} cannot be copied into (no TRANSFER_DST usage)",
                on.device_name
            )));
        }
        let (format, output) = pick_format(&formats).ok_or_else(|| {
            VulkanError::NoSuitableDevice(format!(
                "{} offers no 8-bit RGBA/BGRA format for this window: {formats:?}",
                on.device_name
            ))
        })?;
        let extent = pick_extent(&capabilities, window_size);
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let image_count = match capabilities.max_image_count {
            0 => capabilities.min_image_count + 1,
            max => (capabilities.min_image_count + 1).min(max),
        };
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(capabilities.current_transform)
            .composite_alpha(pick_composite_alpha(capabilities.supported_composite_alpha))
            .present_mode(pick_present_mode(&modes, vsync))
            .clipped(true);
        // SAFETY: `info` refers to the live surface, which has no other swapchain.
        let handle =
            unsafe { on.swapchain_fn.create_swapchain(&info, None) }.during("creating the swapchain")?;
        let mut swapchain = Self { handle, images: Vec::new(), extent, output, rendered: Vec::new() };
        if let Err(error) = swapchain.fill(on) {
            // SAFETY: nothing was submitted with the new swapchain yet.
            unsafe { swapchain.destroy(on) };
            return Err(error);
        }
        Ok(Some(swapchain))
    }

    fn fill(&mut self, on: &SwapchainDevice) -> Result<(), VulkanError> {
        // SAFETY: the swapchain is live.
        self.images = unsafe { on.swapchain_fn.get_swapchain_images(self.handle) }
            .during("listing the swapchain's images")?;
        for _ in &self.images {
            // SAFETY: plain creation on the live device.
            let semaphore = unsafe { on.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                .during("creating a present semaphore")?;
            self.rendered.push(semaphore);
        }
        Ok(())
    }

    /// # Safety
    /// `on` is what the swapchain was made with, and nothing in flight uses the swapchain or
    /// its semaphores (the device is idle).
    pub unsafe fn destroy(&mut self, on: &SwapchainDevice) {
        // SAFETY: the caller's contract.
        unsafe {
            for semaphore in self.rendered.drain(..) {
                on.device.destroy_semaphore(semaphore, None);
            }
            on.swapchain_fn.destroy_swapchain(self.handle, None);
        }
        self.images.clear();
    }

    pub fn handle(&self) -> vk::SwapchainKHR {
        self.handle
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The display output whose bytes a plain copy puts into an image in the right order.
    pub fn output(&self) -> PixelOutput {
        self.output
    }

    /// The image `index` (from `vkAcquireNextImageKHR`) names.
    pub fn image(&self, index: u32) -> vk::Image {
        self.images[index as usize]
    }

    /// The semaphore that the frame for image `index` signals and its present waits on.
    pub fn rendered(&self, index: u32) -> vk::Semaphore {
        self.rendered[index as usize]
    }
}

/// Undefined to transfer-destination, the copy of the tightly packed pixels, then to
/// present-source.
///
/// # Safety
/// `command` is recording on `device`; the buffer holds `extent`'s pixels, tightly packed in
/// the image's format; the image is a swapchain image of `extent` acquired for this frame; both
/// outlive the submission.
pub unsafe fn record_copy_to_present_image(
    device: &ash::Device,
    command: vk::CommandBuffer,
    buffer: vk::Buffer,
    image: vk::Image,
    extent: vk::Extent2D,
) {
    let range = vk::ImageSubresourceRange::default()
        .aspect_mask(vk::ImageAspectFlags::COLOR)
        .level_count(1)
        .layer_count(1);
    let to_transfer = vk::ImageMemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::empty())
        .dst_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .old_layout(vk::ImageLayout::UNDEFINED)
        .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range);
    let to_present = to_transfer
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::empty())
        .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
        .new_layout(vk::ImageLayout::PRESENT_SRC_KHR);
    let region = vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default().aspect_mask(vk::ImageAspectFlags::COLOR).layer_count(1),
        )
        .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 });
    let none = vk::DependencyFlags::empty();
    let transfer = vk::PipelineStageFlags::TRANSFER;
    // SAFETY: the caller's contract.
    unsafe {
        device.cmd_pipeline_barrier(command, transfer, transfer, none, &[], &[], &[to_transfer]);
        device.cmd_copy_buffer_to_image(
            command,
            buffer,
            image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
        );
        let end = vk::PipelineStageFlags::BOTTOM_OF_PIPE;
        device.cmd_pipeline_barrier(command, transfer, end, none, &[], &[], &[to_present]);
    }
}

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
