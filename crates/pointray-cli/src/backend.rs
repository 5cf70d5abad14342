//! Choosing the renderer: a ray-tracing GPU when there is one, else the CPU backend.

use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use pointray_io::MemoryBudget;
use pointray_render::{
    Backend, BackendChoice, DeviceOptions, DeviceSelector, device_options_from_environment,
};

use std::str::FromStr;

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
    #[command(flatten)]
    pub gpu_memory: GpuMemoryArg,
}

/// `--gpu-memory`, for every command that may trace on a GPU.
#[derive(Args, Clone, Copy)]
pub struct GpuMemoryArg {
    /// GPU memory a scene may take, building included, e.g. `40G` (default: the device's).
    /// A large point set is split into more tiles to fit. Where point sets still do not fit,
    /// `render`, `view` and `bench scale` stream their tiles: every tile from a coarse level,
    /// and those the camera sees, largest on screen first, in full as far as the budget allows;
    /// the other commands refuse the scene.
    #[arg(long = "gpu-memory", value_name = "SIZE", value_parser = MemoryBudget::from_str)]
    pub budget: Option<MemoryBudget>,
}

/// `--backend auto|vulkan|cpu`.
pub fn backend_choice() -> impl TypedValueParser<Value = BackendChoice> {
    PossibleValuesParser::new(BackendChoice::NAMES).map(|name| name.parse().expect("a listed name"))
}

/// The renderer the flags ask for.
pub fn open_backend(
    choice: BackendChoice,
    device: &DeviceSelector,
    gpu_memory: Option<MemoryBudget>,
) -> anyhow::Result<Backend> {
    let backend = Backend::open(choice, device, device_options(gpu_memory))?;
    if gpu_memory.is_some() && matches!(backend, Backend::Cpu) {
        eprintln!("note: --gpu-memory budgets the Vulkan backend; the CPU backend renders, without it");
    }
    Ok(backend)
}

/// The environment's device options, with `--gpu-memory`.
pub fn device_options(gpu_memory: Option<MemoryBudget>) -> DeviceOptions {
    DeviceOptions { gpu_memory: gpu_memory.map(|budget| budget.bytes), ..device_options_from_environment() }
}
