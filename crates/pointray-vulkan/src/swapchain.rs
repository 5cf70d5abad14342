//! A window's swapchain: images that display pixels are copied into, recreated when the
//! window changes size or the surface reports it out of date.
//!
//! Built from raw handles rather than the renderer's context, so that a presenter with its own
//! device (the viewer's host-copy path, for machines whose GPU cannot ray trace) shares it
//! with `WindowTarget`: the swapchain and the copy into its images. `present_loop.rs` has the
//! frame loop around them.

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
