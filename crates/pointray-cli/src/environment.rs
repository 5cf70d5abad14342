//! The environment switches, read once here at the command line's edge and handed down as
//! settings: the libraries never read the environment.

use std::path::PathBuf;

use pointray_vulkan::DeviceOptions;

/// `POINTRAY_VALIDATION=1` turns on the Khronos validation layer; `POINTRAY_HIT_REORDERING=off`
/// leaves shader execution reordering out of the device.
pub fn device_options() -> DeviceOptions {
    DeviceOptions {
        validation: std::env::var("POINTRAY_VALIDATION").is_ok_and(|value| value == "1"),
        hit_reordering: std::env::var("POINTRAY_HIT_REORDERING").as_deref() != Ok("off"),
    }
}

/// The data folder: `POINTRAY_DATA` (larger sets than the checkout holds), else the checkout's
/// `data/` seen from the current folder.
pub fn data_dir() -> PathBuf {
    std::env::var_os("POINTRAY_DATA").map_or_else(|| PathBuf::from("data"), PathBuf::from)
}
