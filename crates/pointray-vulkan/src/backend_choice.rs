//! Which renderer draws: the Vulkan ray tracer or the CPU renderer. `render`, `bench`,
//! `fidelity` and the viewer all choose by this one rule.

use crate::device_type::DeviceType;
use crate::error::VulkanError;
use crate::renderer::VulkanRenderer;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BackendChoice {
    /// A hardware ray-tracing GPU if there is one, otherwise the CPU renderer.
    #[default]
    Auto,
    Vulkan,
    Cpu,
}

impl BackendChoice {
    /// The names command lines use, in order.
    pub const NAMES: [&'static str; 3] = ["auto", "vulkan", "cpu"];

    /// The Vulkan renderer this choice asks for, opened by `open`; `None` for the CPU
    /// renderer. `Auto` skips CPU Vulkan drivers (lavapipe): on a 2-core machine the CPU
    /// renderer draws the same scenes faster (bench/CPU_VS_LAVAPIPE.md). Only `Vulkan`
    /// fails when no device opens.
    pub fn vulkan_renderer(
        self,
        open: impl FnOnce() -> Result<VulkanRenderer, VulkanError>,
    ) -> Result<Option<VulkanRenderer>, VulkanError> {
        match self {
            Self::Cpu => Ok(None),
            Self::Vulkan => open().map(Some),
            Self::Auto => {
                Ok(open().ok().filter(|renderer| renderer.device_info().device_type != DeviceType::Cpu))
            }
        }
    }
}

impl std::str::FromStr for BackendChoice {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "auto" => Ok(Self::Auto),
            "vulkan" => Ok(Self::Vulkan),
            "cpu" => Ok(Self::Cpu),
            other => Err(format!("unknown backend `{other}` (expected auto, vulkan or cpu)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_and_cpu_opens_nothing() {
        let parsed: Vec<BackendChoice> = BackendChoice::NAMES.iter().map(|n| n.parse().unwrap()).collect();
        assert_eq!(parsed, [BackendChoice::Auto, BackendChoice::Vulkan, BackendChoice::Cpu]);
        assert!("gpu".parse::<BackendChoice>().is_err());
        let never = || -> Result<VulkanRenderer, VulkanError> { panic!("the CPU choice opens no device") };
        assert!(BackendChoice::Cpu.vulkan_renderer(never).unwrap().is_none());
        let missing = || Err(VulkanError::NoSuitableDevice("none".into()));
        assert!(BackendChoice::Auto.vulkan_renderer(missing).unwrap().is_none());
        let missing = || Err(VulkanError::NoSuitableDevice("none".into()));
        assert!(BackendChoice::Vulkan.vulkan_renderer(missing).is_err());
    }
}
