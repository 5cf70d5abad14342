//! What kind of device a Vulkan driver reports.

use ash::vk;

/// `VkPhysicalDeviceType`, as pointray ranks devices by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeviceType {
    DiscreteGpu,
    IntegratedGpu,
    VirtualGpu,
    /// A CPU implementation of Vulkan, such as lavapipe.
    Cpu,
    Other,
}

impl DeviceType {
    pub(crate) fn of(device_type: vk::PhysicalDeviceType) -> Self {
        match device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => Self::DiscreteGpu,
            vk::PhysicalDeviceType::INTEGRATED_GPU => Self::IntegratedGpu,
            vk::PhysicalDeviceType::VIRTUAL_GPU => Self::VirtualGpu,
            vk::PhysicalDeviceType::CPU => Self::Cpu,
            _ => Self::Other,
        }
    }

    /// Lower is better: discrete GPUs first, CPU implementations last.
    pub(crate) fn preference(self) -> u32 {
        match self {
            Self::DiscreteGpu => 0,
            Self::IntegratedGpu => 1,
            Self::VirtualGpu => 2,
            Self::Other => 3,
            Self::Cpu => 4,
        }
    }
}

impl std::fmt::Display for DeviceType {
    /// Vulkan's own name for the type.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::DiscreteGpu => "DISCRETE_GPU",
            Self::IntegratedGpu => "INTEGRATED_GPU",
            Self::VirtualGpu => "VIRTUAL_GPU",
            Self::Cpu => "CPU",
            Self::Other => "OTHER",
        })
    }
}
