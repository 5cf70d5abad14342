//! Tracing straight into a window: each frame acquires a swapchain image, traces the display
//! output (sRGB8, in the image's byte order) into a device-local buffer, copies that buffer
//! into the image (`vkCmdCopyBufferToImage`) and presents it, all on the renderer's device
//! and queue. Nothing goes through host memory unless a frame is kept for a screenshot.

use std::sync::Arc;

use ash::vk;
use pointray_scene::RenderSettings;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::binding_table::ShaderBindingTable;
use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::pipeline::RayTracingPipeline;
use crate::prepared_scene::PreparedScene;
use crate::present_loop::{PresentLoop, Presented};
use crate::renderer::VulkanRenderer;
use crate::swapchain::{SwapchainDevice, record_copy_to_present_image};
use crate::trace::{record_read_back, record_trace_done_barrier, record_trace_rays, validate};
use crate::trace_target::{PixelOutput, TargetBuffers, TraceTarget};

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
    frames: PresentLoop,
    target: TraceTarget,
    /// Whether the last submitted frame was copied to the read-back buffer.
    kept: bool,
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
        let on = create_surface(context, display, window)?;
        // SAFETY: the renderer's live device and queue, and a new surface on its instance;
        // `Drop` destroys the loop before the surface.
        let frames = unsafe { PresentLoop::new(on.clone(), window_size, vsync) };
        let frames = frames.inspect_err(|_| {
            // SAFETY: nothing uses the surface (the loop cleaned up what it made).
            unsafe { on.surface_fn.destroy_surface(on.surface, None) }
        })?;
        Ok(Self {
            frames,
            target: TraceTarget::new(PixelOutput::Display),
            kept: false,
            context: context.clone(),
        })
    }

    /// The window's new size; the swapchain and the trace target follow before the next frame.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.frames.resize(width, height);
    }

    pub fn set_vsync(&mut self, vsync: bool) {
        self.frames.set_vsync(vsync);
    }

    pub fn vsync(&self) -> bool {
        self.frames.vsync()
    }

    /// The size frames are traced at (the swapchain's); `None` while the window has no area.
    pub fn extent(&mut self) -> Result<Option<(u32, u32)>, VulkanError> {
        self.ensure_swapchain()?;
        Ok(self.frames.swapchain().map(|s| (s.extent().width, s.extent().height)))
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
        self.frames.wait_for_last_frame()?;
        self.ensure_swapchain()?;
        let Some(swapchain) = self.frames.swapchain() else { return Ok(Presented::Skipped) };
        let (extent, output) = (swapchain.extent(), swapchain.output());
        let settings = RenderSettings { width: extent.width, height: extent.height, ..*settings };
        let (pipeline, table) = renderer.pipeline_for(settings.integrator)?;
        validate(&settings, &self.context, pipeline)?;
        let Some(index) = self.frames.acquire()? else { return Ok(Presented::Skipped) };
        if self.target.output() != output {
            self.target = TraceTarget::new(output);
        }
        let buffers = self.target.bind(&self.context, pipeline, scene, &settings)?;
        let image = self.frames.swapchain().expect("checked above").image(index);
        let frame = FrameCommands { pipeline, table, image, extent, buffers, settings: &settings, read_back };
        // SAFETY: the frame's buffers live in `target`, which is rebound only after the next
        // acquire has waited for this frame.
        unsafe {
            self.frames.submit(index, |device, command| record_frame(&self.context, device, command, &frame))
        }?;
        self.kept = read_back == ReadBack::Keep;
        self.frames.present(index)
    }

    /// The last presented frame's pixels, when it was presented with `ReadBack::Keep`.
    pub fn shown_rgba8(&self) -> Result<DisplayImage, VulkanError> {
        let Some(swapchain) = self.frames.swapchain().filter(|_| self.kept) else {
            return Err(VulkanError::InvalidSettings("the last frame was not kept for reading back".into()));
        };
        self.frames.wait_for_last_frame()?;
        let mut rgba8 = self.target.read_back()?.to_vec();
        if swapchain.output() == PixelOutput::DisplayBgra {
            rgba8.chunks_exact_mut(4).for_each(|pixel| pixel.swap(0, 2));
        }
        let extent = swapchain.extent();
        Ok(DisplayImage { width: extent.width, height: extent.height, rgba8 })
    }

    /// Rebuilds the swapchain when the window changed; a rebuild drops the kept frame.
    fn ensure_swapchain(&mut self) -> Result<(), VulkanError> {
        if self.frames.ensure_swapchain()? {
            self.kept = false;
        }
        Ok(())
    }
}

impl Drop for WindowTarget {
    fn drop(&mut self) {
        self.frames.destroy();
        let on = self.frames.device();
        // SAFETY: the loop, the only user of the surface, is destroyed.
        unsafe { on.surface_fn.destroy_surface(on.surface, None) };
    }
}

/// A surface on the window, checked to be presentable from the renderer's queue, with the
/// renderer's device and queue.
fn create_surface(
    context: &GpuContext,
    display: RawDisplayHandle,
    window: RawWindowHandle,
) -> Result<SwapchainDevice, VulkanError> {
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
    Ok(SwapchainDevice {
        device: context.device.clone(),
        physical: context.physical,
        queue: context.queue,
        queue_family: family,
        surface: handle,
        surface_fn,
        swapchain_fn,
        device_name: context.info.name.clone(),
    })
}

/// What one frame records besides the trace's own buffers.
struct FrameCommands<'a> {
    pipeline: &'a RayTracingPipeline,
    table: &'a ShaderBindingTable,
    image: vk::Image,
    extent: vk::Extent2D,
    buffers: &'a TargetBuffers,
    settings: &'a RenderSettings,
    read_back: ReadBack,
}

/// Records the trace, the copy into the acquired image and, when asked, the read-back.
///
/// # Safety
/// `command` is recording on the renderer's device; the frame's buffers and image outlive
/// the submission.
unsafe fn record_frame(
    context: &GpuContext,
    device: &ash::Device,
    command: vk::CommandBuffer,
    frame: &FrameCommands<'_>,
) {
    // SAFETY: the caller's contract.
    unsafe {
        record_trace_rays(context, command, frame.pipeline, frame.table, frame.buffers, frame.settings);
        record_trace_done_barrier(device, command);
        let written = frame.buffers.written.handle;
        record_copy_to_present_image(device, command, written, frame.image, frame.extent);
        if frame.read_back == ReadBack::Keep {
            record_read_back(device, command, frame.buffers);
        }
    }
}
