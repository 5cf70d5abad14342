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
    pub(crate) fn vk(what: &'static str) -> impl FnOnce(vk::Result) -> Self {
        move |result| Self::Present { what, result }
    }
}
