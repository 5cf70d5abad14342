//! What can go wrong while choosing a backend and drawing with it.

use pointray_vulkan::VulkanError;

#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    /// `--backend vulkan` (or its like) was asked for and no Vulkan device opened.
    #[error("the Vulkan backend was asked for, but no Vulkan device opened: {0}")]
    VulkanUnavailable(#[source] VulkanError),
    /// The Vulkan renderer failed while preparing or tracing a scene.
    #[error("the Vulkan backend failed: {0}")]
    Vulkan(#[from] VulkanError),
    /// A prepped map could not be made ready for casting rays on the CPU.
    #[error(transparent)]
    Lidar(Box<pointray_lidar::LidarError>),
    /// The CPU backend was handed a scene the Vulkan backend made ready.
    #[error("the CPU backend cannot trace a scene the Vulkan backend prepared")]
    CpuGivenVulkanScene,
}
