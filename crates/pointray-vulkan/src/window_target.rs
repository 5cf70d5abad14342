//! Tracing straight into a window: each frame acquires a swapchain image, traces the display
//! output (sRGB8, in the image's byte order) into a device-local buffer, copies that buffer
//! into the image (`vkCmdCopyBufferToImage`) and presents it, all on the renderer's device
//! and queue. Nothing goes through host memory unless a frame is kept for a screenshot.

use std::sync::Arc;

use ash::vk;
use pointray_scene::RenderSettings;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::prepared_scene::PreparedScene;
use crate::renderer::VulkanRenderer;
use crate::swapchain::{Swapchain, SwapchainDevice, record_copy_to_present_image};
use crate::trace::{record_read_back, record_trace_done_barrier, record_trace_rays, validate};
use crate::trace_target::{PixelOutput, TargetBuffers, TraceTarget};

/// A window surface and the loaders its swapchain calls go through.
struct Surface {
    handle: vk::SurfaceKHR,
    surface_fn: ash::khr::surface::Instance,
    swapchain_fn: ash::khr::swapchain::Device,
}

impl Surface {
    /// What the swapchain on this surface is made with: the renderer's device.
    fn swapchain_device<'a>(&'a self, context: &'a GpuContext) -> SwapchainDevice<'a> {
        SwapchainDevice {
            device: &context.device,
            physical: context.physical,
            surface: self.handle,
            surface_fn: &self.surface_fn,
            swapchain_fn: &self.swapchain_fn,
            device_name: &context.info.name,
        }
    }
}

/// What `WindowTarget::present` did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presented {
    Shown,
    /// The window has no area or its swapchain had to be rebuilt; nothing was shown.
    Skipped,
}

/// Whether a presented frame is also copied to host memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReadBack {
    No,
    /// Kept for `WindowTarget::shown_rgba8` (screenshots).
    Keep,
}

/// The sRGB8 RGBA pixels of a presented frame, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DisplayImage {
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
}

/// A window's swapchain on a renderer made with `VulkanRenderer::for_window`, and the
/// display-output trace target that feeds it. One frame is in flight at a time.
pub struct WindowTarget {
    // Field order is drop order; `Drop` destroys the raw handles while the context lives.
    swapchain: Option<Swapchain>,
    target: TraceTarget,
    command_pool: vk::CommandPool,
    commands: vk::CommandBuffer,
    acquired: vk::Semaphore,
    in_flight: vk::Fence,
    window_size: (u32, u32),
    vsync: bool,
    stale: bool,
    /// Whether the last submitted frame was copied to the read-back buffer.
    kept: bool,
    surface: Surface,
    context: Arc<GpuContext>,
}

impl WindowTarget {
    /// A target on the window (the handles stay valid until the target is dropped), presenting
    /// with FIFO (`vsync`) or mailbox/immediate. An error naming the device when its queue
    /// cannot present to this window.
    pub fn new(
        renderer: &VulkanRenderer,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        window_size: (u32, u32),
        vsync: bool,
    ) -> Result<Self, VulkanError> {
        let context = &renderer.context;
        if !context.instance.presents {
            return Err(VulkanError::InvalidSettings(
                "a window target needs a renderer made with VulkanRenderer::for_window".into(),
            ));
        }
        let surface = create_surface(context, display, window)?;
        let mut window_target = Self {
            swapchain: None,
            target: TraceTarget::new(PixelOutput::Display),
            command_pool: vk::CommandPool::null(),
            commands: vk::CommandBuffer::null(),
            acquired: vk::Semaphore::null(),
            in_flight: vk::Fence::null(),
            window_size,
            vsync,
            stale: true,
            kept: false,
            surface,
            context: context.clone(),
        };
        // On failure, `Drop` destroys what was made so far (null handles are ignored).
        window_target.create_sync_objects()?;
        Ok(window_target)
    }

    fn create_sync_objects(&mut self) -> Result<(), VulkanError> {
        let device = &self.context.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.context.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: plain creations on the live device, destroyed in `Drop`.
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

    /// The window's new size; the swapchain and the trace target follow before the next frame.
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

    /// The size frames are traced at (the swapchain's); `None` while the window has no area.
    pub fn extent(&mut self) -> Result<Option<(u32, u32)>, VulkanError> {
        self.ensure_swapchain()?;
        Ok(self.swapchain.as_ref().map(|s| (s.extent().width, s.extent().height)))
    }

    /// Traces `scene` with `settings` at the swapchain's size (the settings' own size is
    /// ignored) straight into the next swapchain image and presents it.
    pub fn present(
        &mut self,
        renderer: &VulkanRenderer,
        scene: &PreparedScene,
        settings: &RenderSettings,
        read_back: ReadBack,
    ) -> Result<Presented, VulkanError> {
        renderer.ensure_prepared_here(scene)?;
        if !Arc::ptr_eq(&renderer.context, &self.context) {
            return Err(VulkanError::InvalidSettings("the window target belongs to another renderer".into()));
        }
        self.wait_for_last_frame()?;
        self.ensure_swapchain()?;
        let Some(swapchain) = &self.swapchain else { return Ok(Presented::Skipped) };
        let (extent, output) = (swapchain.extent(), swapchain.output());
        let settings = RenderSettings { width: extent.width, height: extent.height, ..*settings };
        validate(&settings, &self.context)?;
        // SAFETY: the fence wait above: no earlier frame still waits on `acquired`.
        let acquired = unsafe {
            self.surface.swapchain_fn.acquire_next_image(
                swapchain.handle(),
                u64::MAX,
                self.acquired,
                vk::Fence::null(),
            )
        };
        let index = match acquired {
            Ok((index, suboptimal)) => {
                self.stale |= suboptimal;
                index
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                return Ok(Presented::Skipped);
            }
            Err(result) => return Err(VulkanError::from_vk("acquiring a swapchain image", result)),
        };
        if self.target.output() != output {
            self.target = TraceTarget::new(output);
        }
        let buffers = self.target.bind(&self.context, &renderer.pipeline, scene, &settings)?;
        let swapchain = self.swapchain.as_ref().expect("checked above");
        submit_frame(
            &self.context,
            renderer,
            FrameCommands {
                commands: self.commands,
                acquired: self.acquired,
                in_flight: self.in_flight,
                swapchain,
                index,
                buffers,
                settings: &settings,
                read_back,
            },
        )?;
        self.kept = read_back == ReadBack::Keep;
        self.present_image(index)
    }

    fn present_image(&mut self, index: u32) -> Result<Presented, VulkanError> {
        let swapchain = self.swapchain.as_ref().expect("a frame was just submitted to it");
        let (swapchains, indices, waits) = ([swapchain.handle()], [index], [swapchain.rendered(index)]);
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and its frame submitted, signalling `waits`.
        match unsafe { self.surface.swapchain_fn.queue_present(self.context.queue, &info) } {
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

    /// The last presented frame's pixels, when it was presented with `ReadBack::Keep`.
    pub fn shown_rgba8(&self) -> Result<DisplayImage, VulkanError> {
        let Some(swapchain) = self.swapchain.as_ref().filter(|_| self.kept) else {
            return Err(VulkanError::InvalidSettings("the last frame was not kept for reading back".into()));
        };
        self.wait_for_last_frame()?;
        let mut rgba8 = self.target.read_back()?.to_vec();
        if swapchain.output() == PixelOutput::DisplayBgra {
            rgba8.chunks_exact_mut(4).for_each(|pixel| pixel.swap(0, 2));
        }
        let extent = swapchain.extent();
        Ok(DisplayImage { width: extent.width, height: extent.height, rgba8 })
    }

    fn wait_for_last_frame(&self) -> Result<(), VulkanError> {
        // SAFETY: the fence belongs to this device.
        unsafe { self.context.device.wait_for_fences(&[self.in_flight], true, u64::MAX) }
            .during("waiting for the last frame")
    }

    /// Rebuilds the swapchain when the window changed; none while the window has no area.
    fn ensure_swapchain(&mut self) -> Result<(), VulkanError> {
        if !self.stale {
            return Ok(());
        }
        // SAFETY: the device is live; waiting makes every swapchain object idle.
        unsafe { self.context.device.device_wait_idle() }.during("waiting before a swapchain rebuild")?;
        self.kept = false;
        let on = self.surface.swapchain_device(&self.context);
        if let Some(mut old) = self.swapchain.take() {
            // SAFETY: made with `on`; the device is idle.
            unsafe { old.destroy(on) };
        }
        if self.window_size.0 > 0 && self.window_size.1 > 0 {
            // SAFETY: the renderer's live device and this target's surface and loaders; the old
            // swapchain was destroyed above.
            self.swapchain = unsafe { Swapchain::new(on, self.window_size, self.vsync) }?;
        }
        self.stale = false;
        Ok(())
    }
}

impl Drop for WindowTarget {
    fn drop(&mut self) {
        // SAFETY: after the wait nothing uses these objects; null handles are ignored.
        unsafe {
            let _ = self.context.device.device_wait_idle();
            if let Some(mut swapchain) = self.swapchain.take() {
                swapchain.destroy(self.surface.swapchain_device(&self.context));
            }
            let device = &self.context.device;
            device.destroy_fence(self.in_flight, None);
            device.destroy_semaphore(self.acquired, None);
            device.destroy_command_pool(self.command_pool, None);
            self.surface.surface_fn.destroy_surface(self.surface.handle, None);
        }
    }
}

/// A surface on the window, checked to be presentable from the renderer's queue.
fn create_surface(
    context: &GpuContext,
    display: RawDisplayHandle,
    window: RawWindowHandle,
) -> Result<Surface, VulkanError> {
    let instance = &context.instance;
    // SAFETY: the caller keeps the window alive for as long as the surface.
    let handle =
        unsafe { ash_window::create_surface(&instance.entry, &instance.instance, display, window, None) }
            .during("creating the window's surface")?;
    let surface_fn = ash::khr::surface::Instance::new(&instance.entry, &instance.instance);
    let family = context.queue_family;
    // SAFETY: plain query; the family index is the device's own.
    let presents =
        unsafe { surface_fn.get_physical_device_surface_support(context.physical, family, handle) };
    if !presents.unwrap_or(false) {
        // SAFETY: nothing uses the surface yet.
        unsafe { surface_fn.destroy_surface(handle, None) };
        return Err(VulkanError::NoSuitableDevice(format!(
            "{}: its ray-tracing queue family {family} cannot present to this window",
            context.info.name
        )));
    }
    let swapchain_fn = ash::khr::swapchain::Device::new(&instance.instance, &context.device);
    Ok(Surface { handle, surface_fn, swapchain_fn })
}

/// What one frame's submission records into and signals.
struct FrameCommands<'a> {
    commands: vk::CommandBuffer,
    acquired: vk::Semaphore,
    in_flight: vk::Fence,
    swapchain: &'a Swapchain,
    index: u32,
    buffers: &'a TargetBuffers,
    settings: &'a RenderSettings,
    read_back: ReadBack,
}

/// Records the trace and the copy into the acquired image, and submits them: the copy waits
/// for the image, the present waits for the copy, the fence says when the frame is done.
fn submit_frame(
    context: &GpuContext,
    renderer: &VulkanRenderer,
    frame: FrameCommands<'_>,
) -> Result<(), VulkanError> {
    let device = &context.device;
    let command = frame.commands;
    let image = frame.swapchain.image(frame.index);
    // SAFETY: the fence wait in `present` made the command buffer idle; it is re-recorded
    // whole; every resource it uses lives until the fence signals.
    unsafe {
        device.reset_fences(&[frame.in_flight]).during("resetting the frame fence")?;
        device
            .reset_command_buffer(command, vk::CommandBufferResetFlags::empty())
            .during("resetting the window's commands")?;
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        device.begin_command_buffer(command, &begin).during("recording a window frame")?;
        record_trace_rays(
            context,
            command,
            &renderer.pipeline,
            &renderer.table,
            frame.buffers,
            frame.settings,
        );
        record_trace_done_barrier(device, command);
        let (written, extent) = (frame.buffers.written.handle, frame.swapchain.extent());
        record_copy_to_present_image(device, command, written, image, extent);
        if frame.read_back == ReadBack::Keep {
            record_read_back(device, command, frame.buffers);
        }
        device.end_command_buffer(command).during("recording a window frame")?;
        let (waits, stages) = ([frame.acquired], [vk::PipelineStageFlags::TRANSFER]);
        let (commands, signals) = ([command], [frame.swapchain.rendered(frame.index)]);
        let submit = vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&stages)
            .command_buffers(&commands)
            .signal_semaphores(&signals);
        device.queue_submit(context.queue, &[submit], frame.in_flight).during("submitting a window frame")
    }
}
