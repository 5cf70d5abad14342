//! The backend that draws both scenes. The CPU backend is built in; others (Vulkan) are
//! passed in by the caller, so that this crate needs no GPU library.

use pointray_scene::{RenderSettings, RenderedImage, Scene};

pub type RenderError = Box<dyn std::error::Error + Send + Sync>;

pub trait ImageRenderer {
    /// Names the backend in reports.
    fn name(&self) -> String;
    fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<RenderedImage, RenderError>;
}

/// `pointray-cpu`, the reference renderer.
pub struct CpuImageRenderer;

impl ImageRenderer for CpuImageRenderer {
    fn name(&self) -> String {
        "cpu".to_owned()
    }

    fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<RenderedImage, RenderError> {
        Ok(pointray_cpu::render(scene, settings))
    }
}
