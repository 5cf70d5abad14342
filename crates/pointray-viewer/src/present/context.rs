//! The presentation context: the window's surface and a device and queue that can copy into
//! it and present it.
//!
//! For the CPU backend's frames, which are in host memory: it has its own instance and any
//! device that can present (the CPU backend is the fallback for machines whose GPU cannot
//! ray trace, so pointray-vulkan's renderer, and its `WindowTarget`, may not exist there).
//! The viewer copies the host pixels into the swapchain (see `presenter.rs`).

use ash::vk;
use pointray_vulkan::SwapchainDevice;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::instance::PresentInstance;
use crate::error::ViewerError;

pub(crate) struct PresentContext {
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) queue_family: u32,
    pub(crate) memory: vk::PhysicalDeviceMemoryProperties,
    pub(crate) surface: vk::SurfaceKHR,
    pub(crate) surface_fn: ash::khr::surface::Instance,
    swapchain_fn: ash::khr::swapchain::Device,
    /// Names the device in errors.
    device_name: String,
    // Last: dropped after the device and surface made from it.
    pub(crate) instance: PresentInstance,
}

impl PresentContext {
    pub(crate) fn new(
        display: RawDisplayHandle,
        window: RawWindowHandle,
        validation: bool,
    ) -> Result<Self, ViewerError> {
        let instance = PresentInstance::new(display, validation)?;
        let surface_fn = ash::khr::surface::Instance::new(&instance.entry, &instance.instance);
        // SAFETY: the handles come from a live window that outlives the presenter.
        let surface =
            unsafe { ash_window::create_surface(&instance.entry, &instance.instance, display, window, None) }
                .map_err(ViewerError::vk("vkCreate*SurfaceKHR"))?;
        let opened = open_device(&instance.instance, &surface_fn, surface);
        let (physical, queue_family, device) = match opened {
            Ok(opened) => opened,
            Err(error) => {
                // SAFETY: nothing else uses the surface yet.
                unsafe { surface_fn.destroy_surface(surface, None) };
                return Err(error);
            }
        };
        // SAFETY: queue 0 of the family was requested at device creation.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        // SAFETY: plain queries on a live physical device.
        let (memory, properties) = unsafe {
            (
                instance.instance.get_physical_device_memory_properties(physical),
                instance.instance.get_physical_device_properties(physical),
            )
        };
        let device_name = properties
            .device_name_as_c_str()
            .map_or_else(|_| "the presenting device".to_owned(), |name| name.to_string_lossy().into_owned());
        let swapchain_fn = ash::khr::swapchain::Device::new(&instance.instance, &device);
        Ok(Self {
            device,
            queue,
            physical,
            queue_family,
            memory,
            surface,
            surface_fn,
            swapchain_fn,
            device_name,
            instance,
        })
    }

    /// What the window's frames are presented with: this context's device, queue and surface.
    pub(crate) fn swapchain_device(&self) -> SwapchainDevice {
        SwapchainDevice {
            device: self.device.clone(),
            physical: self.physical,
            queue: self.queue,
            queue_family: self.queue_family,
            surface: self.surface,
            surface_fn: self.surface_fn.clone(),
            swapchain_fn: self.swapchain_fn.clone(),
            device_name: self.device_name.clone(),
        }
    }

    /// A memory type with all of `flags` among those `bits` allows.
    pub(crate) fn memory_type(&self, bits: u32, flags: vk::MemoryPropertyFlags) -> Option<u32> {
        let types = &self.memory.memory_types[..self.memory.memory_type_count as usize];
        (0..types.len() as u32)
            .find(|&i| bits & (1 << i) != 0 && types[i as usize].property_flags.contains(flags))
    }
}

impl Drop for PresentContext {
    fn drop(&mut self) {
        // SAFETY: the presenter destroyed every device object before dropping the context.
        unsafe {
            self.device.destroy_device(None);
            self.surface_fn.destroy_surface(self.surface, None);
        }
    }
}

/// The first device with a queue family that does graphics or transfer and can present to
/// `surface`, and the swapchain extension.
fn open_device(
    instance: &ash::Instance,
    surface_fn: &ash::khr::surface::Instance,
    surface: vk::SurfaceKHR,
) -> Result<(vk::PhysicalDevice, u32, ash::Device), ViewerError> {
    // SAFETY: plain enumeration on a live instance.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(ViewerError::vk("vkEnumeratePhysicalDevices"))?;
    let (physical, family) = devices
        .iter()
        .find_map(|&device| presenting_family(instance, surface_fn, surface, device).map(|f| (device, f)))
        .ok_or_else(|| {
            ViewerError::PresentSetup("no Vulkan device can present to this window (VK_KHR_swapchain)".into())
        })?;
    let priorities = [1.0f32];
    let queues =
        [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
    let extensions = [ash::khr::swapchain::NAME.as_ptr()];
    let info =
        vk::DeviceCreateInfo::default().queue_create_infos(&queues).enabled_extension_names(&extensions);
    // SAFETY: every pointer in `info` lives until the call returns.
    let device = unsafe { instance.create_device(physical, &info, None) }
        .map_err(ViewerError::vk("vkCreateDevice"))?;
    Ok((physical, family, device))
}

fn presenting_family(
    instance: &ash::Instance,
    surface_fn: &ash::khr::surface::Instance,
    surface: vk::SurfaceKHR,
    device: vk::PhysicalDevice,
) -> Option<u32> {
    // SAFETY: plain queries on an enumerated device.
    let (families, extensions) = unsafe {
        (
            instance.get_physical_device_queue_family_properties(device),
            instance.enumerate_device_extension_properties(device).unwrap_or_default(),
        )
    };
    let has_swapchain =
        extensions.iter().any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == ash::khr::swapchain::NAME));
    if !has_swapchain {
        return None;
    }
    let copies = vk::QueueFlags::GRAPHICS | vk::QueueFlags::TRANSFER;
    (0..families.len() as u32).find(|&i| {
        let family = &families[i as usize];
        // SAFETY: plain query; the family index is in range.
        let presents =
            unsafe { surface_fn.get_physical_device_surface_support(device, i, surface) }.unwrap_or(false);
        family.queue_flags.intersects(copies) && presents
    })
}
