//! Everything that can go wrong in the Vulkan backend, with messages that say what to do.

use ash::vk;

#[derive(Debug, thiserror::Error)]
pub enum VulkanError {
    #[error(
        "could not load the Vulkan loader (libvulkan.so.1): {0}; install it (scripts/install-system-deps.sh)"
    )]
    LoaderMissing(#[from] ash::LoadingError),
    #[error(
        "the Khronos validation layer VK_LAYER_KHRONOS_validation was asked for (POINTRAY_VALIDATION=1) but is not installed"
    )]
    ValidationLayerMissing,
    #[error("no Vulkan device can ray trace point sets:\n{0}")]
    NoSuitableDevice(String),
    #[error("no Vulkan device can present to this window: {0}")]
    NoPresentingDevice(String),
    #[error("the GPU was lost (device lost) during {0}; the driver may have reset it after a hang")]
    DeviceLost(&'static str),
    #[error("out of {kind} memory during {during}; try a smaller scene or resolution")]
    OutOfMemory { kind: &'static str, during: &'static str },
    #[error("Vulkan call failed during {during}: {result}")]
    Call { during: &'static str, result: vk::Result },
    #[error("memory allocation failed during {during}: {message}")]
    Allocation { during: &'static str, message: String },
    #[error("{0}")]
    OverBudget(String),
    #[error("the scene cannot be rendered: {0}")]
    InvalidScene(String),
    #[error("the render settings are invalid: {0}")]
    InvalidSettings(String),
}

impl VulkanError {
    /// Whether the machine has no usable Vulkan device for us: no loader, no validation layer
    /// when one was asked for, or no device that can ray trace. Callers fall back (or, in
    /// tests outside CI, skip) on these; every other error is a real failure.
    pub fn is_no_device(&self) -> bool {
        matches!(
            self,
            Self::LoaderMissing(_)
                | Self::ValidationLayerMissing
                | Self::NoSuitableDevice(_)
                | Self::NoPresentingDevice(_)
        )
    }

    /// Classifies a failed Vulkan call so that device loss and exhaustion read clearly.
    pub(crate) fn from_vk(during: &'static str, result: vk::Result) -> Self {
        match result {
            vk::Result::ERROR_DEVICE_LOST => Self::DeviceLost(during),
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => Self::OutOfMemory { kind: "GPU", during },
            vk::Result::ERROR_OUT_OF_HOST_MEMORY => Self::OutOfMemory { kind: "host", during },
            _ => Self::Call { during, result },
        }
    }

    pub(crate) fn from_allocation(during: &'static str, error: gpu_allocator::AllocationError) -> Self {
        match error {
            gpu_allocator::AllocationError::OutOfMemory => Self::OutOfMemory { kind: "GPU", during },
            other => Self::Allocation { during, message: other.to_string() },
        }
    }
}

/// Adds the stage name to a raw `vk::Result`.
pub(crate) trait VkContext<T> {
    fn during(self, stage: &'static str) -> Result<T, VulkanError>;
}

impl<T> VkContext<T> for Result<T, vk::Result> {
    fn during(self, stage: &'static str) -> Result<T, VulkanError> {
        self.map_err(|result| VulkanError::from_vk(stage, result))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_missing_loader_layer_or_device_means_no_device() {
        assert!(VulkanError::ValidationLayerMissing.is_no_device());
        assert!(VulkanError::NoSuitableDevice("none".into()).is_no_device());
        assert!(VulkanError::NoPresentingDevice("none".into()).is_no_device());
        assert!(!VulkanError::DeviceLost("tracing").is_no_device());
        assert!(!VulkanError::InvalidSettings("zero width".into()).is_no_device());
        assert!(!VulkanError::from_vk("tracing", vk::Result::ERROR_INITIALIZATION_FAILED).is_no_device());
    }
}
