//! The environment switches, read once here at the command line's edge and handed down as
//! settings: the libraries never read the environment.

use pointray_vulkan::DeviceOptions;

/// `POINTRAY_VALIDATION=1` turns on the Khronos validation layer; `POINTRAY_HIT_REORDERING=off`
/// leaves shader execution reordering out of the device.
pub fn device_options() -> DeviceOptions {
    DeviceOptions {
        validation: std::env::var("POINTRAY_VALIDATION").is_ok_and(|value| value == "1"),
        hit_reordering: std::env::var("POINTRAY_HIT_REORDERING").as_deref() != Ok("off"),
    }
}
