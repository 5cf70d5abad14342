//! The renderer a scene is drawn by.

use pointray_scene::{RenderSettings, RenderedImage, Scene};
use pointray_vulkan::{BackendChoice, DeviceOptions, DeviceSelector, VulkanError, VulkanRenderer};

pub enum Backend {
    Vulkan(Box<VulkanRenderer>),
    Cpu,
}

impl Backend {
    /// The renderer `choice` asks for, on `device` when it is Vulkan.
    pub fn open(
        choice: BackendChoice,
        device: &DeviceSelector,
        options: DeviceOptions,
    ) -> Result<Self, VulkanError> {
        let renderer = choice.vulkan_renderer(|| VulkanRenderer::new(device.clone(), options))?;
        Ok(renderer.map_or(Backend::Cpu, |renderer| Backend::Vulkan(Box::new(renderer))))
    }

    pub fn describe(&self) -> String {
        match self {
            Backend::Vulkan(renderer) => format!("vulkan ({})", renderer.device_name()),
            Backend::Cpu => format!("cpu ({} threads)", rayon::current_num_threads()),
        }
    }

    pub fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<RenderedImage, VulkanError> {
        match self {
            Backend::Vulkan(renderer) => renderer.render(scene, settings),
            Backend::Cpu => Ok(pointray_cpu::render(scene, settings)),
        }
    }
}
