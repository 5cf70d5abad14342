//! The renderer a scene is drawn by.

use pointray_cpu::CpuRenderer;
use pointray_scene::{RenderSettings, RenderedImage, Scene};
use pointray_vulkan::{
    BackendChoice, DeviceOptions, DeviceSelector, SceneLayout, TileResidency, VulkanError, VulkanRenderer,
};

use crate::ready_scene::{ReadyScene, Tracer};

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

    /// Prepares and traces one frame, and says where a streamed scene's tiles stood for it.
    pub fn render(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
    ) -> Result<(RenderedImage, Option<TileResidency>), VulkanError> {
        let mut ready = self.prepare(scene, settings)?;
        let residency = ready.stream_tiles(settings)?;
        Ok((self.trace(&ready, settings)?, residency))
    }

    /// `scene` made ready for frames with `settings`' buffer layout.
    pub fn prepare(&self, scene: &Scene, settings: &RenderSettings) -> Result<ReadyScene, VulkanError> {
        Ok(match self {
            Backend::Vulkan(renderer) => {
                let stream_tiles_for = Some((settings.width, settings.height));
                let layout = SceneLayout { stream_tiles_for, ..SceneLayout::for_settings(settings) };
                ReadyScene::Vulkan(Box::new(renderer.prepare_with_layout(scene, layout)?))
            }
            Backend::Cpu => ReadyScene::Cpu(Box::new(CpuRenderer::new(scene))),
        })
    }

    /// A frame of a scene this backend made ready.
    pub fn trace(&self, ready: &ReadyScene, settings: &RenderSettings) -> Result<RenderedImage, VulkanError> {
        match self.tracer(ready)? {
            Tracer::Vulkan(renderer, prepared) => renderer.trace(prepared, settings),
            Tracer::Cpu(renderer) => Ok(renderer.render(settings)),
        }
    }

    /// What traces `ready`'s frames; an error when the Vulkan backend made it ready and this
    /// is the CPU one.
    pub fn tracer<'a>(&'a self, ready: &'a ReadyScene) -> Result<Tracer<'a>, VulkanError> {
        match (self, ready) {
            (Backend::Vulkan(renderer), ReadyScene::Vulkan(prepared)) => {
                Ok(Tracer::Vulkan(renderer, prepared))
            }
            (_, ReadyScene::Cpu(renderer)) => Ok(Tracer::Cpu(renderer)),
            (Backend::Cpu, ReadyScene::Vulkan(_)) => Err(VulkanError::InvalidScene(
                "the scene was prepared by the Vulkan backend, not the CPU one".into(),
            )),
        }
    }
}
