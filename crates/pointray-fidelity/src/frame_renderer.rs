//! The backend that draws both scenes. The CPU backend is built in; others (Vulkan) are
//! passed in by the caller, so that this crate needs no GPU library.

use pointray_scene::{Frame, RenderSettings, Scene};

pub type RenderError = Box<dyn std::error::Error + Send + Sync>;

pub trait FrameRenderer {
    /// Names the backend in reports.
    fn name(&self) -> String;
    fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<Frame, RenderError>;
}

/// `pointray-cpu`, the reference renderer.
pub struct CpuFrameRenderer;

impl FrameRenderer for CpuFrameRenderer {
    fn name(&self) -> String {
        "cpu".to_owned()
    }

    fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<Frame, RenderError> {
        Ok(pointray_cpu::render(scene, settings))
    }
}
