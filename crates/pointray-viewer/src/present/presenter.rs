//! Shows host pixels in the window: each frame is written into a host-visible staging buffer,
//! copied into the acquired swapchain image with `vkCmdCopyBufferToImage`, and presented.
//! One frame is in flight at a time; the CPU renderer's frames are on the host anyway.

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::ByteOrder;
use crate::error::ViewerError;
use pointray_vulkan::validation::MessageCounter;
use pointray_vulkan::{PresentDevice, PresentLoop, Presented, record_copy_to_present_image};

pub struct Presenter {
    frames: PresentLoop,
    // After the loop: dropped once `Drop` has destroyed the loop.
    device: PresentDevice,
}

impl Presenter {
    pub fn new(
        display: RawDisplayHandle,
        window: RawWindowHandle,
        window_size: (u32, u32),
        vsync: bool,
        validation: bool,
    ) -> Result<Self, ViewerError> {
        let device = PresentDevice::new(display, window, validation).map_err(ViewerError::from_swapchain)?;
        // SAFETY: the device's live device, queue, surface and loaders; `Drop` destroys the
        // loop before the device (on failure the loop cleans up what it made).
        let frames = unsafe { PresentLoop::new(device.swapchain_device(), window_size, vsync) }
            .map_err(ViewerError::from_swapchain)?;
        Ok(Self { frames, device })
    }

    /// The window's frames: `resize` and `set_vsync` go to them directly.
    pub fn frames(&mut self) -> &mut PresentLoop {
        &mut self.frames
    }

    /// The size `present` wants its pixels in (after `prepare`), and their byte order.
    pub fn target(&mut self) -> Result<Option<(vk::Extent2D, ByteOrder)>, ViewerError> {
        self.frames.ensure_swapchain().map_err(ViewerError::from_swapchain)?;
        Ok(self.frames.swapchain().map(|s| (s.extent(), ByteOrder::from(s.output()))))
    }

    /// Validation messages of the presentation context; still counting during teardown.
    pub fn message_counter(&self) -> std::sync::Arc<MessageCounter> {
        self.device.message_counter()
    }

    /// Shows `pixels` (4 bytes each, in `target()`'s size and byte order).
    pub fn present(&mut self, pixels: &[u8]) -> Result<Presented, ViewerError> {
        self.frames.ensure_swapchain().map_err(ViewerError::from_swapchain)?;
        let Some(swapchain) = self.frames.swapchain() else { return Ok(Presented::Skipped) };
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
        // Waits for the last frame: the staging buffer is free to reuse after this.
        let Some(index) = self.frames.acquire().map_err(ViewerError::from_swapchain)? else {
            return Ok(Presented::Skipped);
        };
        let buffer = self.device.stage(pixels).map_err(ViewerError::from_swapchain)?;
        let image = self.frames.swapchain().expect("an image was just acquired").image(index);
        // SAFETY: the staging buffer lives until the next acquire has waited for this frame;
        // the image is the acquired one, of `extent`.
        unsafe {
            self.frames.submit(index, |device, command| {
                record_copy_to_present_image(device, command, buffer, image, extent)
            })
        }
        .map_err(ViewerError::from_swapchain)?;
        self.frames.present(index).map_err(ViewerError::from_swapchain)
    }
}

impl Drop for Presenter {
    fn drop(&mut self) {
        // Waits for the device first.
        self.frames.destroy();
    }
}
