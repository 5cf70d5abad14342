//! A device that only presents, for images rendered on the host (the CPU backend): any
//! device that can present to the window, ray tracing or not, since the CPU backend is the
//! fallback for machines whose GPU cannot ray trace. Host pixels reach the swapchain through
//! one staging buffer of gpu-allocator memory.

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::error::{VkContext, VulkanError};
use crate::instance::{Instance, create_instance};
use crate::swapchain::SwapchainDevice;
use crate::validation::MessageCounter;

/// The window's surface, a device and queue that can copy into it and present it, and the
/// staging buffer. Present with a `PresentLoop` on `swapchain_device()`, destroyed first.
pub struct PresentDevice {
    staging: Option<Staging>,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    swapchain: SwapchainDevice,
    // Last: dropped after the device and the surface made from it.
    instance: Instance,
}

struct Staging {
    buffer: vk::Buffer,
    allocation: Allocation,
}

impl PresentDevice {
    /// With `validation`, the Khronos layer checks every call (`message_counter`).
    pub fn new(
        display: RawDisplayHandle,
        window: RawWindowHandle,
        validation: bool,
    ) -> Result<Self, VulkanError> {
        let instance = create_instance(validation, Some(display))?;
        let surface_fn = ash::khr::surface::Instance::new(&instance.entry, &instance.instance);
        // SAFETY: the handles come from a live window that outlives this device.
        let surface =
            unsafe { ash_window::create_surface(&instance.entry, &instance.instance, display, window, None) }
                .during("creating the window's surface")?;
        let opened = open_presenting_device(&instance.instance, &surface_fn, surface);
        let (physical, queue_family, device) = match opened {
            Ok(opened) => opened,
            Err(error) => {
                // SAFETY: nothing else uses the surface yet.
                unsafe { surface_fn.destroy_surface(surface, None) };
                return Err(error);
            }
        };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(allocator) => allocator,
            Err(error) => {
                // SAFETY: nothing was made on the device yet.
                unsafe {
                    device.destroy_device(None);
                    surface_fn.destroy_surface(surface, None);
                }
                return Err(VulkanError::from_allocation("creating the memory allocator", error));
            }
        };
        let swapchain = SwapchainDevice {
            // SAFETY: queue 0 of the family was requested at device creation.
            queue: unsafe { device.get_device_queue(queue_family, 0) },
            device_name: crate::device::describe(&instance.instance, physical, 0).name,
            swapchain_fn: ash::khr::swapchain::Device::new(&instance.instance, &device),
            device,
            physical,
            queue_family,
            surface,
            surface_fn,
        };
        Ok(Self { staging: None, allocator: ManuallyDrop::new(Mutex::new(allocator)), swapchain, instance })
    }

    /// What the window's frames are presented with: this device, its queue and surface.
    pub fn swapchain_device(&self) -> SwapchainDevice {
        self.swapchain.clone()
    }

    /// Validation messages; still counting during teardown.
    pub fn message_counter(&self) -> Arc<MessageCounter> {
        self.instance.message_counter()
    }

    /// A buffer holding `bytes` to copy from, grown when they do not fit. The caller has
    /// waited for the last copy out of it (a `PresentLoop::acquire` does).
    pub fn stage(&mut self, bytes: &[u8]) -> Result<vk::Buffer, VulkanError> {
        let fits = self.staging.as_ref().is_some_and(|s| s.allocation.size() >= bytes.len() as u64);
        if !fits {
            self.free_staging();
            self.staging = Some(self.new_staging(bytes.len() as u64)?);
        }
        let staging = self.staging.as_mut().expect("made above");
        let mapped = staging.allocation.mapped_slice_mut().expect("host memory is mapped");
        mapped[..bytes.len()].copy_from_slice(bytes);
        Ok(staging.buffer)
    }

    fn new_staging(&self, size: u64) -> Result<Staging, VulkanError> {
        let device = &self.swapchain.device;
        let during = "making the staging buffer";
        let info = vk::BufferCreateInfo::default()
            .size(size.max(1))
            .usage(vk::BufferUsageFlags::TRANSFER_SRC)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: the device is alive; the buffer is destroyed on failure or in `free_staging`.
        let buffer = unsafe { device.create_buffer(&info, None) }.during(during)?;
        // SAFETY: `buffer` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let description = AllocationCreateDesc {
            name: "staging",
            requirements,
            location: MemoryLocation::CpuToGpu,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        };
        let allocation =
            self.lock_allocator().allocate(&description).map_err(|e| VulkanError::from_allocation(during, e));
        // SAFETY: the allocation satisfies `requirements` and is bound nowhere else.
        let bound = allocation.and_then(|allocation| {
            unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) }
                .during(during)
                .map(|()| allocation)
        });
        match bound {
            Ok(allocation) => Ok(Staging { buffer, allocation }),
            Err(error) => {
                // SAFETY: the buffer is unused.
                unsafe { device.destroy_buffer(buffer, None) };
                Err(error)
            }
        }
    }

    fn free_staging(&mut self) {
        if let Some(staging) = self.staging.take() {
            // SAFETY: the caller waited for the last copy out of the buffer.
            unsafe { self.swapchain.device.destroy_buffer(staging.buffer, None) };
            let _ = self.lock_allocator().free(staging.allocation);
        }
    }

    fn lock_allocator(&self) -> std::sync::MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

impl Drop for PresentDevice {
    fn drop(&mut self) {
        // SAFETY: the owner destroyed its present loop first; after waiting for the device,
        // nothing uses the staging buffer, and the allocator is dropped before the device.
        unsafe {
            let _ = self.swapchain.device.device_wait_idle();
            self.free_staging();
            ManuallyDrop::drop(&mut self.allocator);
            self.swapchain.device.destroy_device(None);
            self.swapchain.surface_fn.destroy_surface(self.swapchain.surface, None);
        }
    }
}

/// The first device with a queue family that can copy (graphics or transfer) and present to
/// `surface`, and the swapchain extension.
fn open_presenting_device(
    instance: &ash::Instance,
    surface_fn: &ash::khr::surface::Instance,
    surface: vk::SurfaceKHR,
) -> Result<(vk::PhysicalDevice, u32, ash::Device), VulkanError> {
    // SAFETY: plain enumeration on a live instance.
    let devices = unsafe { instance.enumerate_physical_devices() }.during("enumerating devices")?;
    let (physical, family) = devices
        .iter()
        .find_map(|&device| presenting_family(instance, surface_fn, surface, device).map(|f| (device, f)))
        .ok_or_else(|| {
            VulkanError::NoPresentingDevice("none has VK_KHR_swapchain and a queue that presents".into())
        })?;
    let priorities = [1.0f32];
    let queues =
        [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
    let extensions = [ash::khr::swapchain::NAME.as_ptr()];
    let info =
        vk::DeviceCreateInfo::default().queue_create_infos(&queues).enabled_extension_names(&extensions);
    // SAFETY: every pointer in `info` lives until the call returns.
    let device =
        unsafe { instance.create_device(physical, &info, None) }.during("creating the presenting device")?;
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
    let copies = vk::QueueFlags::GRAPHICS | vk::QueueFlags::TRANSFER;
    (0..families.len() as u32).filter(|_| has_swapchain).find(|&i| {
        // SAFETY: plain query; the family index is in range.
        let presents =
            unsafe { surface_fn.get_physical_device_surface_support(device, i, surface) }.unwrap_or(false);
        families[i as usize].queue_flags.intersects(copies) && presents
    })
}
