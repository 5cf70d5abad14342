//! Choosing the renderer: a ray-tracing GPU when there is one, else the CPU backend.

use anyhow::Context;
use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use pointray_scene::{Frame, RenderSettings, Scene};
use pointray_vulkan::{BackendChoice, DeviceSelector, VulkanRenderer};

use crate::environment::device_options;

/// The `--backend` and `--device` flags of the commands that render on either backend and
/// default to `auto`.
#[derive(Args)]
pub struct BackendArgs {
    /// `auto` takes a hardware ray-tracing GPU if there is one, otherwise the CPU backend.
    #[arg(long, default_value = "auto", value_parser = backend_choice())]
    pub backend: BackendChoice,
    /// Vulkan device: `auto`, an index from `pointray devices`, or part of its name.
    #[arg(long, default_value = "auto")]
    pub device: DeviceSelector,
}

/// `--backend auto|vulkan|cpu`.
pub fn backend_choice() -> impl TypedValueParser<Value = BackendChoice> {
    PossibleValuesParser::new(BackendChoice::NAMES).map(|name| name.parse().expect("a listed name"))
}

pub enum Backend {
    Vulkan(Box<VulkanRenderer>),
    Cpu,
}

impl Backend {
    pub fn open(choice: BackendChoice, device: &DeviceSelector) -> anyhow::Result<Self> {
        let open = || VulkanRenderer::new(device.clone(), device_options());
        let renderer = choice.vulkan_renderer(open).context("opening the Vulkan backend")?;
        Ok(renderer.map_or(Backend::Cpu, |renderer| Backend::Vulkan(Box::new(renderer))))
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
