//! The environment switches, for the programs' edges to read once and hand down as settings:
//! the libraries below never read the environment.

use pointray_vulkan::DeviceOptions;

/// `POINTRAY_VALIDATION=1` turns on the Khronos validation layer; `POINTRAY_HIT_REORDERING=off`
/// leaves shader execution reordering out of the device.
pub fn device_options_from_environment() -> DeviceOptions {
    DeviceOptions {
        validation: std::env::var("POINTRAY_VALIDATION").is_ok_and(|value| value == "1"),
        hit_reordering: std::env::var("POINTRAY_HIT_REORDERING").as_deref() != Ok("off"),
        gpu_memory: None,
    }
}
