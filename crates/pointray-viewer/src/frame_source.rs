//! Where frames come from: the Vulkan ray tracer (scene prepared once, camera changed per
//! frame) or the CPU renderer (BVHs built once, camera and lights set per frame).

use pointray_cpu::CpuRenderer;
use pointray_scene::{Frame, Light, RenderSettings, Scene};
use pointray_vulkan::{DeviceSelector, PreparedScene, VulkanRenderer};

use crate::error::ViewerError;

/// Which renderer draws the frames; as `pointray render --backend`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RenderBackend {
    /// A hardware ray-tracing GPU if there is one, else the CPU renderer (CPU Vulkan drivers
    /// such as lavapipe are slower than the CPU renderer, as for `pointray render`).
    #[default]
    Auto,
    Vulkan,
    Cpu,
}

pub(crate) enum FrameSource {
    Vulkan {
        // Before the renderer: its GPU objects go first.
        prepared: Box<PreparedScene>,
        lights: Vec<Light>,
        renderer: Box<VulkanRenderer>,
    },
    /// Its BVHs are built once; each frame only sets the camera and the lights.
    Cpu(Box<CpuRenderer>),
}

impl FrameSource {
    pub(crate) fn open(
        choice: RenderBackend,
        device: &DeviceSelector,
        validation: bool,
        scene: &Scene,
    ) -> Result<Self, ViewerError> {
        let open = || VulkanRenderer::with_validation(device.clone(), validation);
        let renderer = match choice {
            RenderBackend::Cpu => None,
            RenderBackend::Vulkan => Some(open()?),
            RenderBackend::Auto => {
                open().ok().filter(|r| !r.device_info().device_type.to_ascii_lowercase().contains("cpu"))
            }
        };
        match renderer {
            Some(renderer) => {
                let prepared = Box::new(renderer.prepare(scene)?);
                Ok(Self::Vulkan { prepared, lights: scene.lights.clone(), renderer: Box::new(renderer) })
            }
            None => Ok(Self::Cpu(Box::new(CpuRenderer::new(scene)))),
        }
    }

    pub(crate) fn describe(&self) -> String {
        match self {
            Self::Vulkan { renderer, .. } => format!("vulkan ({})", renderer.device_name()),
            Self::Cpu(_) => "cpu".into(),
        }
    }

    pub(crate) fn is_cpu(&self) -> bool {
        matches!(self, Self::Cpu(_))
    }

    pub(crate) fn vulkan_device_name(&self) -> Option<&str> {
        match self {
            Self::Vulkan { renderer, .. } => Some(renderer.device_name()),
            Self::Cpu(_) => None,
        }
    }

    pub(crate) fn validation_messages(&self) -> u32 {
        match self {
            Self::Vulkan { renderer, .. } => renderer.validation_messages(),
            Self::Cpu(_) => 0,
        }
    }

    /// Renders `scene` (its camera and lights as they are now) with `settings`.
    pub(crate) fn render(&mut self, scene: &Scene, settings: &RenderSettings) -> Result<Frame, ViewerError> {
        match self {
            Self::Vulkan { prepared, lights, renderer } => {
                if *lights != scene.lights {
                    // Lights live in a GPU buffer built by `prepare`; re-preparing is the
                    // public way to change them (a key press, not every frame).
                    **prepared = renderer.prepare(scene)?;
                    *lights = scene.lights.clone();
                }
                prepared.camera = scene.camera;
                Ok(renderer.trace(prepared, settings)?)
            }
            Self::Cpu(renderer) => {
                // Neither is in a BVH, so setting them every frame costs nothing.
                renderer.set_camera(scene.camera);
                renderer.set_lights(scene.lights.clone());
                Ok(renderer.render(settings))
            }
        }
    }
}
