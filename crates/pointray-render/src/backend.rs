//! The renderer a scene is drawn by, and the one rule by which a `BackendChoice` becomes one:
//! `render`, `view`, `bench`, `fidelity` and the Python module all open their renderer here.

use pointray_cpu::CpuRenderer;
use pointray_scene::{RenderSettings, RenderedImage, Scene};
use pointray_vulkan::{
    DeviceOptions, DeviceSelector, DeviceType, SceneLayout, TileResidency, VulkanError, VulkanRenderer,
};
use raw_window_handle::RawDisplayHandle;

use crate::backend_choice::BackendChoice;
use crate::error::BackendError;
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
    ) -> Result<Self, BackendError> {
        Self::chosen(choice, || VulkanRenderer::new(device.clone(), options))
    }

    /// As `open`, with a Vulkan renderer that can also present to `display`'s windows (the
    /// viewer's direct path).
    pub fn open_for_window(
        choice: BackendChoice,
        device: &DeviceSelector,
        options: DeviceOptions,
        display: RawDisplayHandle,
    ) -> Result<Self, BackendError> {
        Self::chosen(choice, || VulkanRenderer::for_window(device.clone(), options, display))
    }

    /// The Vulkan renderer alone, for what only it measures (`bench`'s GPU suites); an
    /// error when no device opens.
    pub fn open_vulkan(
        device: &DeviceSelector,
        options: DeviceOptions,
    ) -> Result<VulkanRenderer, BackendError> {
        VulkanRenderer::new(device.clone(), options).map_err(BackendError::VulkanUnavailable)
    }

    /// The rule: `Cpu` opens no device; `Vulkan` opens one or fails; `Auto` takes the device
    /// `open` gives unless it is none or a CPU Vulkan driver (lavapipe): on a 2-core machine
    /// the CPU renderer draws the same scenes faster (bench/CPU_VS_LAVAPIPE.md).
    fn chosen(
        choice: BackendChoice,
        open: impl FnOnce() -> Result<VulkanRenderer, VulkanError>,
    ) -> Result<Self, BackendError> {
        let renderer = match choice {
            BackendChoice::Cpu => None,
            BackendChoice::Vulkan => Some(open().map_err(BackendError::VulkanUnavailable)?),
            BackendChoice::Auto => {
                open().ok().filter(|renderer| renderer.device_info().device_type != DeviceType::Cpu)
            }
        };
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
    ) -> Result<(RenderedImage, Option<TileResidency>), BackendError> {
        let mut ready = self.prepare(scene, settings)?;
        let residency = ready.stream_tiles(settings)?;
        Ok((self.trace(&ready, settings)?, residency))
    }

    /// `scene` made ready for frames with `settings`' buffer layout.
    pub fn prepare(&self, scene: &Scene, settings: &RenderSettings) -> Result<ReadyScene, BackendError> {
        Ok(match self {
            Backend::Vulkan(renderer) => {
                let layout = SceneLayout::for_frames(settings);
                ReadyScene::Vulkan(Box::new(renderer.prepare_with_layout(scene, layout)?))
            }
            Backend::Cpu => ReadyScene::Cpu(Box::new(CpuRenderer::new(scene))),
        })
    }

    /// A frame of a scene this backend made ready.
    pub fn trace(
        &self,
        ready: &ReadyScene,
        settings: &RenderSettings,
    ) -> Result<RenderedImage, BackendError> {
        match self.tracer(ready)? {
            Tracer::Vulkan(renderer, prepared) => Ok(renderer.trace(prepared, settings)?),
            Tracer::Cpu(renderer) => Ok(renderer.render(settings)),
        }
    }

    /// What traces `ready`'s frames; an error when the Vulkan backend made it ready and this
    /// is the CPU one.
    pub fn tracer<'a>(&'a self, ready: &'a ReadyScene) -> Result<Tracer<'a>, BackendError> {
        match (self, ready) {
            (Backend::Vulkan(renderer), ReadyScene::Vulkan(prepared)) => {
                Ok(Tracer::Vulkan(renderer, prepared))
            }
            (_, ReadyScene::Cpu(renderer)) => Ok(Tracer::Cpu(renderer)),
            (Backend::Cpu, ReadyScene::Vulkan(_)) => Err(BackendError::CpuGivenVulkanScene),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_opens_nothing_auto_falls_back_and_vulkan_fails_without_a_device() {
        let never = || -> Result<VulkanRenderer, VulkanError> { panic!("the CPU choice opens no device") };
        assert!(matches!(Backend::chosen(BackendChoice::Cpu, never), Ok(Backend::Cpu)));
        let missing = || Err(VulkanError::NoSuitableDevice("none".into()));
        assert!(matches!(Backend::chosen(BackendChoice::Auto, missing), Ok(Backend::Cpu)));
        let missing = || Err(VulkanError::NoSuitableDevice("none".into()));
        let refused = Backend::chosen(BackendChoice::Vulkan, missing);
        assert!(matches!(refused, Err(BackendError::VulkanUnavailable(_))));
    }
}
