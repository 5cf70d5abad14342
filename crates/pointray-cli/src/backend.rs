//! Choosing the renderer: a ray-tracing GPU when there is one, else the CPU backend.

use anyhow::Context;
use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use pointray_render::{Backend, BackendChoice, DeviceSelector, device_options_from_environment};

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

/// The renderer the flags ask for.
pub fn open_backend(choice: BackendChoice, device: &DeviceSelector) -> anyhow::Result<Backend> {
    Backend::open(choice, device, device_options_from_environment()).context("opening the Vulkan backend")
}
