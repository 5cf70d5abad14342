//! Choosing a physical device that can ray trace point sets.

use std::ffi::CStr;

use ash::vk;

use crate::device_type::DeviceType;
use crate::error::{VkContext, VulkanError};
use crate::instance::create_instance;

/// The device extensions the renderer needs.
pub(crate) const REQUIRED_EXTENSIONS: [&CStr; 3] = [
    ash::khr::acceleration_structure::NAME,
    ash::khr::ray_tracing_pipeline::NAME,
    ash::khr::deferred_host_operations::NAME,
];

/// Which device to render on.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum DeviceSelector {
    /// The best suitable device: a discrete GPU before an integrated one, lavapipe last.
    #[default]
    Auto,
    /// The first suitable device whose name contains this text (case-insensitive).
    Name(String),
    /// The device at this index of `list_devices()`.
    Index(usize),
}

impl std::str::FromStr for DeviceSelector {
    type Err = std::convert::Infallible;

    /// A number selects by index, `auto` (or nothing) picks, anything else matches names.
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let text = text.trim();
        Ok(if text.is_empty() || text.eq_ignore_ascii_case("auto") {
            Self::Auto
        } else if let Ok(index) = text.parse() {
            Self::Index(index)
        } else {
            Self::Name(text.to_owned())
        })
    }
}

/// How a device is opened: the switches a command line reads from its environment
/// (`POINTRAY_VALIDATION`, `POINTRAY_HIT_REORDERING`) and hands down.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceOptions {
    /// The Khronos validation layer, counting every message it reports.
    pub validation: bool,
    /// Enables `VK_NV_ray_tracing_invocation_reorder` where the device offers it; off, the
    /// extension stays out of the device, so the benchmark can measure what merely enabling
    /// it does to the driver.
    pub hit_reordering: bool,
    /// Bytes of GPU memory each scene prepared on the device may take, building included,
    /// unless its `SceneLayout` names a budget; `None` is the device-local heap.
    pub gpu_memory: Option<u64>,
}

impl Default for DeviceOptions {
    fn default() -> Self {
        Self { validation: false, hit_reordering: true, gpu_memory: None }
    }
}

impl DeviceOptions {
    /// The defaults with validation on, as tests open devices.
    pub const VALIDATED: Self = Self { validation: true, hit_reordering: true, gpu_memory: None };
}

/// One physical device as the loader reports it, and whether pointray can use it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub device_type: DeviceType,
    /// `major.minor.patch` of the Vulkan API the driver supports.
    pub api_version: String,
    /// The driver's own name and version text (e.g. "llvmpipe" / "Mesa 25.0.7").
    pub driver: String,
    /// Why the device cannot be used; `None` when it can.
    pub rejection: Option<String>,
    /// Whether it offers shader execution reordering (`VK_NV_ray_tracing_invocation_reorder`).
    pub hit_reordering: bool,
    /// Bytes of its largest device-local memory heap.
    pub device_local_bytes: u64,
    /// The most primitives one bottom-level structure may hold (`maxPrimitiveCount`); 0 for
    /// an unusable device.
    pub max_blas_primitives: u64,
}

impl std::fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "[{}] {} ({}, Vulkan {}, {})",
            self.index, self.name, self.device_type, self.api_version, self.driver
        )?;
        match &self.rejection {
            Some(reason) => write!(f, ": unusable, {reason}")?,
            None => write!(f, ": usable")?,
        }
        if self.hit_reordering {
            write!(f, ", with hit reordering")?;
        }
        Ok(())
    }
}

/// Every device the Vulkan loader finds, with the reason each unusable one is rejected.
pub fn list_devices() -> Result<Vec<DeviceInfo>, VulkanError> {
    let instance = create_instance(false, None)?;
    // SAFETY: the instance is alive for this call.
    let devices = unsafe { instance.instance.enumerate_physical_devices() }.during("enumerating devices")?;
    Ok(devices
        .iter()
        .enumerate()
        .map(|(index, &device)| describe(&instance.instance, device, index))
        .collect())
}

fn version_text(version: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(version),
        vk::api_version_minor(version),
        vk::api_version_patch(version)
    )
}

pub(crate) fn describe(instance: &ash::Instance, device: vk::PhysicalDevice, index: usize) -> DeviceInfo {
    let mut driver_properties = vk::PhysicalDeviceDriverProperties::default();
    let mut properties = vk::PhysicalDeviceProperties2::default().push_next(&mut driver_properties);
    // SAFETY: `device` came from this instance.
    unsafe { instance.get_physical_device_properties2(device, &mut properties) };
    let base = properties.properties;
    let name = base.device_name_as_c_str().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let driver_name = driver_properties
        .driver_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let driver_info = driver_properties
        .driver_info_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let rejection = rejection(instance, device, base.api_version).err();
    DeviceInfo {
        index,
        name,
        device_type: DeviceType::of(base.device_type),
        api_version: version_text(base.api_version),
        driver: format!("{driver_name} {driver_info}").trim().to_owned(),
        max_blas_primitives: if rejection.is_none() { max_blas_primitives(instance, device) } else { 0 },
        rejection,
        hit_reordering: supports_hit_reordering(instance, device),
        device_local_bytes: device_local_bytes(instance, device),
    }
}

fn device_local_bytes(instance: &ash::Instance, device: vk::PhysicalDevice) -> u64 {
    // SAFETY: `device` came from this instance.
    let memory = unsafe { instance.get_physical_device_memory_properties(device) };
    let heaps = &memory.memory_heaps[..memory.memory_heap_count as usize];
    heaps
        .iter()
        .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
        .map(|h| h.size)
        .max()
        .unwrap_or(0)
}

/// Only for a device with `VK_KHR_acceleration_structure`, whose properties these are.
fn max_blas_primitives(instance: &ash::Instance, device: vk::PhysicalDevice) -> u64 {
    let mut acceleration = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut properties = vk::PhysicalDeviceProperties2::default().push_next(&mut acceleration);
    // SAFETY: `device` came from this instance and has the extension; the chain outlives the call.
    unsafe { instance.get_physical_device_properties2(device, &mut properties) };
    acceleration.max_primitive_count
}

/// Whether `device` has the extension and the feature of shader execution reordering.
pub(crate) fn supports_hit_reordering(instance: &ash::Instance, device: vk::PhysicalDevice) -> bool {
    // SAFETY: `device` came from this instance.
    let extensions = unsafe { instance.enumerate_device_extension_properties(device) }.unwrap_or_default();
    let named = |e: &vk::ExtensionProperties| {
        e.extension_name_as_c_str().is_ok_and(|n| n == ash::nv::ray_tracing_invocation_reorder::NAME)
    };
    if !extensions.iter().any(named) {
        return false;
    }
    let mut reorder = vk::PhysicalDeviceRayTracingInvocationReorderFeaturesNV::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut reorder);
    // SAFETY: `device` came from this instance; the chain outlives the call.
    unsafe { instance.get_physical_device_features2(device, &mut features) };
    reorder.ray_tracing_invocation_reorder == vk::TRUE
}

/// Ok when the device has everything the renderer uses, else the first thing it lacks.
fn rejection(instance: &ash::Instance, device: vk::PhysicalDevice, api_version: u32) -> Result<(), String> {
    if api_version < vk::API_VERSION_1_2 {
        return Err(format!("Vulkan {} is below the 1.2 needed", version_text(api_version)));
    }
    // SAFETY: `device` came from this instance.
    let extensions = unsafe { instance.enumerate_device_extension_properties(device) }
        .map_err(|e| format!("cannot list its extensions ({e})"))?;
    let missing: Vec<String> = REQUIRED_EXTENSIONS
        .iter()
        .filter(|&&needed| !extensions.iter().any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == needed)))
        .map(|needed| needed.to_string_lossy().into_owned())
        .collect();
    if !missing.is_empty() {
        return Err(format!("lacks {}", missing.join(", ")));
    }
    let mut vulkan12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut acceleration = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut ray_tracing = vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut vulkan12)
        .push_next(&mut acceleration)
        .push_next(&mut ray_tracing);
    // SAFETY: `device` came from this instance; the chain outlives the call.
    unsafe { instance.get_physical_device_features2(device, &mut features) };
    if vulkan12.buffer_device_address == vk::FALSE {
        return Err("lacks the bufferDeviceAddress feature".into());
    }
    if acceleration.acceleration_structure == vk::FALSE {
        return Err("lacks the accelerationStructure feature".into());
    }
    if ray_tracing.ray_tracing_pipeline == vk::FALSE {
        return Err("lacks the rayTracingPipeline feature".into());
    }
    compute_queue_family(instance, device).map(|_| ()).ok_or_else(|| "has no compute queue".into())
}

/// A queue family that can run ray-tracing pipelines (any compute-capable family).
pub(crate) fn compute_queue_family(instance: &ash::Instance, device: vk::PhysicalDevice) -> Option<u32> {
    // SAFETY: `device` came from this instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(device) };
    families.iter().position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE)).map(|i| i as u32)
}

/// The index of the device `selector` asks for among `devices`, or an error naming them all.
pub(crate) fn select(devices: &[DeviceInfo], selector: &DeviceSelector) -> Result<usize, VulkanError> {
    let usable = |d: &&DeviceInfo| d.rejection.is_none();
    let chosen = match selector {
        DeviceSelector::Auto => {
            devices.iter().filter(usable).min_by_key(|d| (d.device_type.preference(), d.index))
        }
        DeviceSelector::Name(text) => {
            let text = text.to_lowercase();
            devices.iter().filter(usable).find(|d| d.name.to_lowercase().contains(&text))
        }
        DeviceSelector::Index(index) => devices.iter().filter(usable).find(|d| d.index == *index),
    };
    chosen.map(|d| d.index).ok_or_else(|| {
        let listing = if devices.is_empty() {
            "  the Vulkan loader found no device at all (is a driver, e.g. mesa-vulkan-drivers, installed?)"
                .to_owned()
        } else {
            devices.iter().map(|d| format!("  {d}")).collect::<Vec<_>>().join("\n")
        };
        VulkanError::NoSuitableDevice(format!("none matches {selector:?}; devices found:\n{listing}"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(index: usize, name: &str, device_type: DeviceType, rejection: Option<&str>) -> DeviceInfo {
        DeviceInfo {
            index,
            name: name.into(),
            device_type,
            api_version: "1.3.0".into(),
            driver: String::new(),
            rejection: rejection.map(Into::into),
            hit_reordering: false,
            device_local_bytes: 0,
            max_blas_primitives: 0,
        }
    }

    #[test]
    fn auto_prefers_a_discrete_gpu_over_lavapipe() {
        let devices = [
            info(0, "llvmpipe", DeviceType::Cpu, None),
            info(1, "NVIDIA H100", DeviceType::DiscreteGpu, None),
        ];
        assert_eq!(select(&devices, &DeviceSelector::Auto).unwrap(), 1);
        assert_eq!(select(&devices, &DeviceSelector::Name("LLVM".into())).unwrap(), 0);
    }

    #[test]
    fn rejection_lists_every_device_and_its_reason() {
        let devices =
            [info(0, "old gpu", DeviceType::DiscreteGpu, Some("lacks VK_KHR_ray_tracing_pipeline"))];
        let message = select(&devices, &DeviceSelector::Auto).unwrap_err().to_string();
        assert!(
            message.contains("old gpu") && message.contains("lacks VK_KHR_ray_tracing_pipeline"),
            "{message}"
        );
        assert!(select(&devices, &DeviceSelector::Index(0)).is_err());
    }

    #[test]
    fn selector_parses_indices_names_and_auto() {
        assert_eq!("2".parse::<DeviceSelector>().unwrap(), DeviceSelector::Index(2));
        assert_eq!("auto".parse::<DeviceSelector>().unwrap(), DeviceSelector::Auto);
        assert_eq!("H200".parse::<DeviceSelector>().unwrap(), DeviceSelector::Name("H200".into()));
    }
}
