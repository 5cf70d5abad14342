//! The `--scan` flag, shared by the commands that prep points.

use clap::ValueEnum;
use pointray_surface::ScanMode;

/// Whether prep uses a scan's line structure.
#[derive(Clone, Copy, ValueEnum)]
pub enum Scan {
    /// Elliptical patches along the scan lines (from a ring field, or beams recovered from
    /// elevations) whenever the sensor position is known.
    Auto,
    /// Every cloud as unstructured points.
    Off,
}

impl From<Scan> for ScanMode {
    fn from(scan: Scan) -> Self {
        match scan {
            Scan::Auto => ScanMode::Auto,
            Scan::Off => ScanMode::Off,
        }
    }
}
