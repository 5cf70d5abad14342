//! The logical device and what hangs off it: queue, allocator, extension loaders and the
//! ray-tracing limits. Shared through `Arc` by every GPU resource, so it is dropped last.

use std::mem::ManuallyDrop;
use std::sync::Mutex;

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use raw_window_handle::RawDisplayHandle;

use crate::device::{
    DeviceInfo, DeviceOptions, DeviceSelector, REQUIRED_EXTENSIONS, compute_queue_family, describe, select,
};
use crate::error::{VkContext, VulkanError};
use crate::instance::{Instance, create_instance};

pub(crate) struct GpuContext {
    pub(crate) info: DeviceInfo,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) queue_family: u32,
    pub(crate) acceleration: ash::khr::acceleration_structure::Device,
    pub(crate) ray_tracing: ash::khr::ray_tracing_pipeline::Device,
    pub(crate) ray_tracing_properties: vk::PhysicalDeviceRayTracingPipelinePropertiesKHR<'static>,
    pub(crate) scratch_alignment: u64,
    /// Nanoseconds per timestamp tick; `None` when the queue has no timestamps.
    pub(crate) timestamp_period_ns: Option<f32>,
    /// `DeviceOptions::gpu_memory`: what a scene may take where its layout names no budget.
    pub(crate) gpu_memory: Option<u64>,
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: vk::CommandPool,
    // Declared last: dropped after the device is destroyed in `Drop`.
    pub(crate) instance: Instance,
}

impl GpuContext {
    /// With `display`, the instance can make surfaces for that window system's windows and
    /// the device has `VK_KHR_swapchain`.
    pub(crate) fn new(
        selector: &DeviceSelector,
        options: DeviceOptions,
        display: Option<RawDisplayHandle>,
    ) -> Result<Self, VulkanError> {
        let instance = create_instance(options.validation, display)?;
        // SAFETY: the instance is alive.
        let physicals =
            unsafe { instance.instance.enumerate_physical_devices() }.during("enumerating devices")?;
        let infos: Vec<DeviceInfo> =
            physicals.iter().enumerate().map(|(i, &d)| describe(&instance.instance, d, i)).collect();
        let index = select(&infos, selector)?;
        let physical = physicals[index];
        let family = compute_queue_family(&instance.instance, physical).ok_or_else(|| {
            VulkanError::NoSuitableDevice("the chosen device lost its compute queue".into())
        })?;
        let hit_reordering = infos[index].hit_reordering && options.hit_reordering;
        if instance.presents && !has_swapchain(&instance.instance, physical) {
            return Err(VulkanError::NoSuitableDevice(format!(
                "{} cannot present to windows: it lacks VK_KHR_swapchain",
                infos[index].name
            )));
        }
        let device = create_device(&instance.instance, physical, family, hit_reordering, instance.presents)?;
        // SAFETY: queue 0 of `family` was requested at device creation.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: true,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| VulkanError::from_allocation("creating the memory allocator", e))?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: the device is alive.
        let command_pool =
            unsafe { device.create_command_pool(&pool_info, None) }.during("creating a command pool")?;
        let (ray_tracing_properties, scratch_alignment, timestamp_period_ns) =
            limits(&instance.instance, physical, family);
        Ok(Self {
            // What the device was created with: reordering only if it was enabled.
            info: DeviceInfo { hit_reordering, ..infos[index].clone() },
            acceleration: ash::khr::acceleration_structure::Device::new(&instance.instance, &device),
            ray_tracing: ash::khr::ray_tracing_pipeline::Device::new(&instance.instance, &device),
            physical,
            device,
            queue,
            queue_family: family,
            ray_tracing_properties,
            scratch_alignment,
            timestamp_period_ns,
            gpu_memory: options.gpu_memory,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            command_pool,
            instance,
        })
    }

    /// Records commands with `record`, submits them and waits until the GPU is done.
    pub(crate) fn submit_and_wait(
        &self,
        during: &'static str,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<(), VulkanError> {
        let allocate = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: single-threaded use of the pool; the buffer is freed before returning.
        unsafe {
            let command = self.device.allocate_command_buffers(&allocate).during(during)?[0];
            let result = self.record_submit_wait(command, during, record);
            self.device.free_command_buffers(self.command_pool, &[command]);
            result
        }
    }

    unsafe fn record_submit_wait(
        &self,
        command: vk::CommandBuffer,
        during: &'static str,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<(), VulkanError> {
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: `command` is a fresh primary buffer of this device; the fence is waited on
        // and destroyed before returning.
        unsafe {
            self.device.begin_command_buffer(command, &begin).during(during)?;
            record(command);
            self.device.end_command_buffer(command).during(during)?;
            let fence = self.device.create_fence(&vk::FenceCreateInfo::default(), None).during(during)?;
            let commands = [command];
            let submit = vk::SubmitInfo::default().command_buffers(&commands);
            let result = self
                .device
                .queue_submit(self.queue, &[submit], fence)
                .and_then(|()| self.device.wait_for_fences(&[fence], true, u64::MAX));
            self.device.destroy_fence(fence, None);
            result.during(during)
        }
    }

    pub(crate) fn validation_messages(&self) -> u32 {
        self.instance.validation_messages()
    }

    pub(crate) fn message_counter(&self) -> std::sync::Arc<crate::validation::MessageCounter> {
        self.instance.message_counter()
    }
}

impl Drop for GpuContext {
    fn drop(&mut self) {
        // SAFETY: every resource holding an Arc to this context is gone; the allocator is
        // dropped (freeing its memory blocks) before the device it allocated from.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.command_pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
        }
    }
}

/// Whether `physical` offers `VK_KHR_swapchain`.
fn has_swapchain(instance: &ash::Instance, physical: vk::PhysicalDevice) -> bool {
    // SAFETY: `physical` came from this instance.
    let extensions = unsafe { instance.enumerate_device_extension_properties(physical) }.unwrap_or_default();
    extensions.iter().any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == ash::khr::swapchain::NAME))
}

/// The device, with shader execution reordering enabled when `hit_reordering` (supported)
/// and the swapchain extension when `presents`.
fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    family: u32,
    hit_reordering: bool,
    presents: bool,
) -> Result<ash::Device, VulkanError> {
    let priorities = [1.0];
    let queues =
        [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
    let mut extensions: Vec<*const std::ffi::c_char> =
        REQUIRED_EXTENSIONS.iter().map(|e| e.as_ptr()).collect();
    if hit_reordering {
        extensions.push(ash::nv::ray_tracing_invocation_reorder::NAME.as_ptr());
    }
    if presents {
        extensions.push(ash::khr::swapchain::NAME.as_ptr());
    }
    let mut reorder = vk::PhysicalDeviceRayTracingInvocationReorderFeaturesNV::default()
        .ray_tracing_invocation_reorder(true);
    let mut vulkan12 = vk::PhysicalDeviceVulkan12Features::default().buffer_device_address(true);
    let mut acceleration =
        vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
    let mut ray_tracing =
        vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default().ray_tracing_pipeline(true);
    let mut create_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .push_next(&mut vulkan12)
        .push_next(&mut acceleration)
        .push_next(&mut ray_tracing);
    if hit_reordering {
        create_info = create_info.push_next(&mut reorder);
    }
    // SAFETY: the chain and arrays outlive the call; the features were checked in `describe`.
    unsafe { instance.create_device(physical, &create_info, None) }.during("creating the logical device")
}

type Limits = (vk::PhysicalDeviceRayTracingPipelinePropertiesKHR<'static>, u64, Option<f32>);

/// Shader-group sizes, the scratch alignment and the timestamp period.
fn limits(instance: &ash::Instance, physical: vk::PhysicalDevice, family: u32) -> Limits {
    let mut ray_tracing = vk::PhysicalDeviceRayTracingPipelinePropertiesKHR::default();
    let mut acceleration = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut properties =
        vk::PhysicalDeviceProperties2::default().push_next(&mut ray_tracing).push_next(&mut acceleration);
    // SAFETY: the chain outlives the call.
    unsafe { instance.get_physical_device_properties2(physical, &mut properties) };
    let period = properties.properties.limits.timestamp_period;
    // SAFETY: `physical` came from this instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    let has_timestamps = families[family as usize].timestamp_valid_bits > 0;
    let scratch = u64::from(acceleration.min_acceleration_structure_scratch_offset_alignment);
    ray_tracing.p_next = std::ptr::null_mut();
    (ray_tracing, scratch.max(1), has_timestamps.then_some(period))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A semaphore left alive when the context goes: the layer reports the leak during
    /// `vkDestroyDevice`, after every owner is gone, and the shared counter still counts it.
    #[test]
    fn the_message_counter_counts_leaks_reported_at_teardown() {
        let context = match GpuContext::new(&DeviceSelector::Auto, DeviceOptions::VALIDATED, None) {
            Ok(context) => context,
            Err(error) if error.is_no_device() => {
                assert!(!std::env::var("CI").is_ok_and(|v| v == "true"), "CI=true but {error}");
                return eprintln!("note: skipping, {error}");
            }
            Err(error) => panic!("the context does not open: {error}"),
        };
        let counter = context.message_counter();
        // SAFETY: a plain creation on the live device; leaking it is the point of the test.
        unsafe { context.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
            .expect("a semaphore");
        assert_eq!(counter.count(), 0, "messages before the teardown (printed above)");
        drop(context);
        assert!(counter.count() >= 1, "the leaked semaphore was not reported at teardown");
    }
}
