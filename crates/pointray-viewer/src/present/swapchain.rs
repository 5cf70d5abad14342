//! The swapchain: images the host pixels are copied into, recreated when the window changes
//! size or the surface says it is out of date.

use ash::vk;

use pointray_vulkan::PixelOutput;
use pointray_vulkan::surface_choice::{self, pick_composite_alpha, pick_extent, pick_present_mode};

use super::context::PresentContext;
use crate::error::ViewerError;

/// How the bytes of one swapchain pixel are ordered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ByteOrder {
    Bgra,
    Rgba,
}

pub(crate) struct Swapchain {
    pub(crate) handle: vk::SwapchainKHR,
    pub(crate) images: Vec<vk::Image>,
    pub(crate) extent: vk::Extent2D,
    pub(crate) byte_order: ByteOrder,
    /// One per image: signalled when the copy into that image is done, waited on by present.
    /// Per image because a present's semaphore may only be reused once its image comes back.
    pub(crate) copy_done: Vec<vk::Semaphore>,
}

impl Swapchain {
    /// `window_size` is used when the surface leaves the extent to the application; `None`
    /// while the window has no area (minimised).
    pub(crate) fn new(
        context: &PresentContext,
        swapchain_fn: &ash::khr::swapchain::Device,
        window_size: (u32, u32),
        vsync: bool,
    ) -> Result<Option<Self>, ViewerError> {
        let (physical, surface, surface_fn) = (context.physical, context.surface, &context.surface_fn);
        // SAFETY: plain queries on the live surface.
        let (capabilities, formats, modes) = unsafe {
            (
                surface_fn
                    .get_physical_device_surface_capabilities(physical, surface)
                    .map_err(ViewerError::vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR"))?,
                surface_fn
                    .get_physical_device_surface_formats(physical, surface)
                    .map_err(ViewerError::vk("vkGetPhysicalDeviceSurfaceFormatsKHR"))?,
                surface_fn
                    .get_physical_device_surface_present_modes(physical, surface)
                    .map_err(ViewerError::vk("vkGetPhysicalDeviceSurfacePresentModesKHR"))?,
            )
        };
        if !capabilities.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_DST) {
            return Err(ViewerError::PresentSetup("the surface's images cannot be copied into".into()));
        }
        let (format, byte_order) = pick_format(&formats)?;
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
        // SAFETY: `info` refers to the live surface; the caller destroyed any previous swapchain.
        let handle = unsafe { swapchain_fn.create_swapchain(&info, None) }
            .map_err(ViewerError::vk("vkCreateSwapchainKHR"))?;
        let mut swapchain = Self { handle, images: Vec::new(), extent, byte_order, copy_done: Vec::new() };
        let filled = swapchain.fill(context, swapchain_fn);
        if let Err(error) = filled {
            swapchain.destroy(&context.device, swapchain_fn);
            return Err(error);
        }
        Ok(Some(swapchain))
    }

    fn fill(
        &mut self,
        context: &PresentContext,
        swapchain_fn: &ash::khr::swapchain::Device,
    ) -> Result<(), ViewerError> {
        // SAFETY: the swapchain is live.
        self.images = unsafe { swapchain_fn.get_swapchain_images(self.handle) }
            .map_err(ViewerError::vk("vkGetSwapchainImagesKHR"))?;
        for _ in &self.images {
            // SAFETY: plain creation on the live device.
            let semaphore =
                unsafe { context.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                    .map_err(ViewerError::vk("vkCreateSemaphore"))?;
            self.copy_done.push(semaphore);
        }
        Ok(())
    }

    /// The caller makes sure the device is idle first.
    pub(crate) fn destroy(&mut self, device: &ash::Device, swapchain_fn: &ash::khr::swapchain::Device) {
        // SAFETY: nothing in flight uses these objects (the device is idle).
        unsafe {
            for semaphore in self.copy_done.drain(..) {
                device.destroy_semaphore(semaphore, None);
            }
            swapchain_fn.destroy_swapchain(self.handle, None);
        }
        self.images.clear();
    }
}

/// The format `pointray_vulkan::surface_choice` picks, as a byte order for the host's bytes.
fn pick_format(formats: &[vk::SurfaceFormatKHR]) -> Result<(vk::SurfaceFormatKHR, ByteOrder), ViewerError> {
    let (format, output) = surface_choice::pick_format(formats).ok_or_else(|| {
        ViewerError::PresentSetup(format!("no 8-bit RGBA/BGRA surface format among {formats:?}"))
    })?;
    let order = match output {
        PixelOutput::DisplayBgra => ByteOrder::Bgra,
        PixelOutput::Display | PixelOutput::Aovs => ByteOrder::Rgba,
    };
    Ok((format, order))
}
