//! The renderer a Python call asks for: `auto`, `vulkan` or `cpu`.

use pointray_scene::{Frame, RenderSettings, Scene};
use pointray_vulkan::{DeviceSelector, VulkanRenderer};

pub enum Backend {
    Vulkan(Box<VulkanRenderer>),
    Cpu,
}

impl Backend {
    pub fn open(choice: &str, device: &str) -> Result<Self, String> {
        let device: DeviceSelector = device.parse().map_err(|e| format!("device: {e}"))?;
        match choice {
            "cpu" => Ok(Backend::Cpu),
            "vulkan" => VulkanRenderer::new(device)
                .map(|renderer| Backend::Vulkan(Box::new(renderer)))
                .map_err(|e| format!("opening the Vulkan backend: {e}")),
            "auto" => Ok(VulkanRenderer::new(device)
                .ok()
                .filter(|renderer| !renderer.device_info().device_type.to_ascii_lowercase().contains("cpu"))
                .map_or(Backend::Cpu, |renderer| Backend::Vulkan(Box::new(renderer)))),
            other => Err(format!("unknown backend `{other}`; give auto, vulkan or cpu")),
        }
    }

    pub fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<Frame, String> {
        match self {
            Backend::Vulkan(renderer) => renderer.render(scene, settings).map_err(|e| e.to_string()),
            Backend::Cpu => Ok(pointray_cpu::render(scene, settings)),
        }
    }
}
