//! What can go wrong while viewing.

use std::path::PathBuf;

use ash::vk;

#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    #[error("cannot open a window: {0}")]
    Window(String),
    #[error("presentation (Vulkan swapchain): {what} failed: {result}")]
    Present { what: &'static str, result: vk::Result },
    #[error("presentation (Vulkan swapchain): {0}")]
    PresentSetup(String),
    #[error("the Vulkan renderer: {0}")]
    Renderer(#[from] pointray_vulkan::VulkanError),
    #[error("{0}")]
    Backend(#[from] pointray_render::BackendError),
    #[error("writing the screenshot {path}: {source}")]
    Screenshot { path: PathBuf, source: Box<pointray_scene::SceneError> },
    #[error("creating the sequence folder {path}: {source}")]
    SequenceDir { path: PathBuf, source: std::io::Error },
    #[error(
        "the Vulkan validation layer reported {0} message(s) during the run or at teardown (printed above)"
    )]
    Validation(u32),
}

impl ViewerError {
    /// A failure of the host-copy presenter (pointray-vulkan's `PresentDevice` and its
    /// swapchain) as a presentation error, not a renderer's: a failed call keeps its result;
    /// an unsuitable device or surface is a setup problem.
    pub(crate) fn from_swapchain(error: pointray_vulkan::VulkanError) -> Self {
        use pointray_vulkan::VulkanError;
        match error {
            VulkanError::NoSuitableDevice(problem) => Self::PresentSetup(problem),
            error @ VulkanError::NoPresentingDevice(_) => Self::PresentSetup(error.to_string()),
            VulkanError::Call { during, result } => Self::Present { what: during, result },
            VulkanError::DeviceLost(during) => {
                Self::Present { what: during, result: vk::Result::ERROR_DEVICE_LOST }
            }
            VulkanError::OutOfMemory { kind: "host", during } => {
                Self::Present { what: during, result: vk::Result::ERROR_OUT_OF_HOST_MEMORY }
            }
            VulkanError::OutOfMemory { during, .. } => {
                Self::Present { what: during, result: vk::Result::ERROR_OUT_OF_DEVICE_MEMORY }
            }
            other => Self::PresentSetup(other.to_string()),
        }
    }
}
