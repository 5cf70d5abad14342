//! Choosing the renderer: a ray-tracing GPU when there is one, else the CPU backend.

use anyhow::Context;
use clap::{Args, ValueEnum};
use pointray_scene::{Frame, RenderSettings, Scene};
use pointray_vulkan::{DeviceSelector, VulkanRenderer};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum BackendChoice {
    /// A hardware ray-tracing GPU if there is one, otherwise the CPU backend.
    #[default]
    Auto,
    Vulkan,
    Cpu,
}

/// The `--backend` and `--device` flags of the commands that render on either backend and
/// default to `auto`.
#[derive(Args)]
pub struct BackendArgs {
    #[arg(long, value_enum, default_value_t = BackendChoice::Auto)]
    pub backend: BackendChoice,
    /// Vulkan device: `auto`, an index from `pointray devices`, or part of its name.
    #[arg(long, default_value = "auto")]
    pub device: DeviceSelector,
}

pub enum Backend {
    Vulkan(Box<VulkanRenderer>),
    Cpu,
}

impl Backend {
    /// `auto` skips CPU Vulkan drivers (lavapipe): on a 2-core machine our CPU backend
    /// renders the same scenes faster (bench/CPU_VS_LAVAPIPE.md).
    pub fn open(choice: BackendChoice, device: &DeviceSelector) -> anyhow::Result<Self> {
        match choice {
            BackendChoice::Cpu => Ok(Backend::Cpu),
            BackendChoice::Vulkan => {
                let renderer = VulkanRenderer::new(device.clone()).context("opening the Vulkan backend")?;
                Ok(Backend::Vulkan(Box::new(renderer)))
            }
            BackendChoice::Auto => Ok(Self::hardware_gpu(device).unwrap_or(Backend::Cpu)),
        }
    }

    fn hardware_gpu(device: &DeviceSelector) -> Option<Self> {
        let renderer = VulkanRenderer::new(device.clone()).ok()?;
        let is_cpu_driver = renderer.device_info().device_type.to_ascii_lowercase().contains("cpu");
        (!is_cpu_driver).then(|| Backend::Vulkan(Box::new(renderer)))
    }

    pub fn describe(&self) -> String {
        match self {
            Backend::Vulkan(renderer) => format!("vulkan ({})", renderer.device_name()),
            Backend::Cpu => format!("cpu ({} threads)", rayon::current_num_threads()),
        }
    }

    pub fn render(&self, scene: &Scene, settings: &RenderSettings) -> anyhow::Result<Frame> {
        match self {
            Backend::Vulkan(renderer) => Ok(renderer.render(scene, settings)?),
            Backend::Cpu => Ok(pointray_cpu::render(scene, settings)),
        }
    }
}
