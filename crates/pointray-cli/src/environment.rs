//! The environment, read here at the command line's edge and handed down as settings: the
//! libraries never read it. The device switches are read by `pointray_render`, which the
//! Python module's edge shares.

use std::path::PathBuf;

/// The data folder: `POINTRAY_DATA` (larger sets than the checkout holds), else the checkout's
/// `data/` seen from the current folder.
pub fn data_dir() -> PathBuf {
    std::env::var_os("POINTRAY_DATA").map_or_else(|| PathBuf::from("data"), PathBuf::from)
}
