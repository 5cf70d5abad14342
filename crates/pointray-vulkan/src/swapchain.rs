//! A window's swapchain: images that traced display pixels are copied into, recreated when
//! the window changes size or the surface reports it out of date.

use ash::vk;

use crate::context::GpuContext;
use crate::error::{VkContext, VulkanError};
use crate::surface_choice::{pick_composite_alpha, pick_extent, pick_format, pick_present_mode};
use crate::trace_target::PixelOutput;

/// A window surface and the loaders its swapchain calls go through.
pub(crate) struct Surface {
    pub(crate) handle: vk::SurfaceKHR,
    pub(crate) surface_fn: ash::khr::surface::Instance,
    pub(crate) swapchain_fn: ash::khr::swapchain::Device,
}

pub(crate) struct Swapchain {
    pub(crate) handle: vk::SwapchainKHR,
    pub(crate) images: Vec<vk::Image>,
    pub(crate) extent: vk::Extent2D,
    /// What the ray generation shader writes so that a plain copy fills an image.
    pub(crate) output: PixelOutput,
    /// One per image: signalled when the frame for that image is done, waited on by present.
    /// Per image because a present's semaphore may be reused only once its image comes back.
    pub(crate) rendered: Vec<vk::Semaphore>,
}

impl Swapchain {
    /// `window_size` is used when the surface leaves the extent to the application; `None`
    /// while the window has no area (minimised).
    pub(crate) fn new(
        context: &GpuContext,
        surface: &Surface,
        window_size: (u32, u32),
        vsync: bool,
    ) -> Result<Option<Self>, VulkanError> {
        let (physical, surface_fn) = (context.physical, &surface.surface_fn);
        // SAFETY: plain queries on the live surface.
        let (capabilities, formats, modes) = unsafe {
            (
                surface_fn
                    .get_physical_device_surface_capabilities(physical, surface.handle)
                    .during("querying the surface's capabilities")?,
                surface_fn
                    .get_physical_device_surface_formats(physical, surface.handle)
                    .during("querying the surface's formats")?,
                surface_fn
                    .get_physical_device_surface_present_modes(physical, surface.handle)
                    .during("querying the surface's present modes")?,
            )
        };
        if !capabilities.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_DST) {
            return Err(VulkanError::NoSuitableDevice(format!(
                "the window's images on {} cannot be copied into (no TRANSFER_DST usage)",
                context.info.name
            )));
        }
        let (format, output) = pick_format(&formats).ok_or_else(|| {
            VulkanError::NoSuitableDevice(format!(
                "{} offers no 8-bit RGBA/BGRA format for this window: {formats:?}",
                context.info.name
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
            .surface(surface.handle)
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
        // SAFETY: `info` refers to the live surface; the caller destroyed any previous swapchain.
        let handle =
            unsafe { surface.swapchain_fn.create_swapchain(&info, None) }.during("creating the swapchain")?;
        let mut swapchain = Self { handle, images: Vec::new(), extent, output, rendered: Vec::new() };
        if let Err(error) = swapchain.fill(context, surface) {
            swapchain.destroy(context, surface);
            return Err(error);
        }
        Ok(Some(swapchain))
    }

    fn fill(&mut self, context: &GpuContext, surface: &Surface) -> Result<(), VulkanError> {
        // SAFETY: the swapchain is live.
        self.images = unsafe { surface.swapchain_fn.get_swapchain_images(self.handle) }
            .during("listing the swapchain's images")?;
        for _ in &self.images {
            // SAFETY: plain creation on the live device.
            let semaphore =
                unsafe { context.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                    .during("creating a present semaphore")?;
            self.rendered.push(semaphore);
        }
        Ok(())
    }

    /// The caller makes sure that nothing in flight uses the swapchain (device idle).
    pub(crate) fn destroy(&mut self, context: &GpuContext, surface: &Surface) {
        // SAFETY: nothing in flight uses these objects.
        unsafe {
            for semaphore in self.rendered.drain(..) {
                context.device.destroy_semaphore(semaphore, None);
            }
            surface.swapchain_fn.destroy_swapchain(self.handle, None);
        }
        self.images.clear();
    }
}
