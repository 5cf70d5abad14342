//! Sensors with their published angles. Ranges and noise are the data sheets' round figures;
//! every spinning preset turns at 10 Hz.

use std::str::FromStr;

use crate::sensor::{Elevations, Sensor, uniform_beams};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensorPreset {
    /// Velodyne HDL-64E: 64 beams, +2° to −24.33°.
    Hdl64,
    /// Velodyne HDL-32E: 32 beams, +10.67° to −30.67°.
    Hdl32,
    /// Velodyne VLP-16 (Puck): 16 beams, ±15°.
    Vlp16,
    /// Ouster OS1-128: 128 beams, ±22.5°.
    Os128,
    /// A static terrestrial scanner on a tripod: a square angular grid from 60° below the
    /// horizon to the zenith.
    Terrestrial,
}

impl SensorPreset {
    pub const ALL: [Self; 5] = [Self::Hdl64, Self::Hdl32, Self::Vlp16, Self::Os128, Self::Terrestrial];

    /// The name the command line takes.
    pub fn key(self) -> &'static str {
        match self {
            Self::Hdl64 => "hdl64",
            Self::Hdl32 => "hdl32",
            Self::Vlp16 => "vlp16",
            Self::Os128 => "os128",
            Self::Terrestrial => "terrestrial",
        }
    }

    pub fn sensor(self) -> Sensor {
        match self {
            Self::Hdl64 => spinning("Velodyne HDL-64E", hdl64_elevations(), 0.1728, 120.0, 0.02),
            // HDL-32E user manual (Velodyne 63-9113), laser vertical angles: −30.67° to +10.67° in
            // steps of 1.33° (exactly 4/3°).
            Self::Hdl32 => {
                spinning("Velodyne HDL-32E", uniform_beams(32, -92.0 / 3.0, 32.0 / 3.0), 0.16, 100.0, 0.02)
            }
            // VLP-16 user manual (Velodyne 63-9243), laser vertical angles: −15° to +15° in
            // steps of 2°.
            Self::Vlp16 => spinning("Velodyne VLP-16", uniform_beams(16, -15.0, 15.0), 0.2, 100.0, 0.03),
            // Ouster OS1 data sheet (rev 6 and 7): 128 channels uniformly spread over a 45°
            // vertical field of view, +22.5° to −22.5°; 1024 columns at 10 Hz.
            Self::Os128 => {
                spinning("Ouster OS1-128", uniform_beams(128, -22.5, 22.5), 360.0 / 1024.0, 120.0, 0.03)
            }
            Self::Terrestrial => terrestrial(),
        }
    }
}

/// Velodyne's HDL-64E S2/S3 data sheets give a vertical field of view of +2° to −24.9° with
/// about 0.4° between beams. The two blocks of 32 lasers are spaced differently; the nominal
/// layout usually quoted puts the upper block 1/3° apart from +2° down to −8.33° and the lower
/// block 1/2° apart from −8.83° down to −24.33°. Each unit's own calibration (its db.xml, see
/// the HDL-64E S2 manual, Velodyne 63-HDL64ES2) moves the beams by a few tenths of a degree.
fn hdl64_elevations() -> Vec<f64> {
    let upper_lowest = 2.0 - 31.0 / 3.0;
    let lower = (1..=32).map(|i| upper_lowest - 0.5 * i as f64).rev();
    let upper = (0..32).rev().map(|i| 2.0 - i as f64 / 3.0);
    lower.chain(upper).collect()
}

/// A spinning sensor turning at 10 Hz: its beams' elevations (degrees, lowest first), its
/// azimuth step (degrees), its maximum range and its range noise (metres).
fn spinning(name: &str, beams: Vec<f64>, azimuth_step_deg: f64, max_range: f64, range_noise: f64) -> Sensor {
    Sensor {
        name: name.into(),
        elevations: Elevations::Beams(beams),
        azimuth_step_deg,
        sweep_seconds: 0.1,
        min_range: 1.0,
        max_range,
        range_noise,
        dropout: 0.0,
        // KITTI's HDL-64E sits 1.73 m above the road.
        mount_height: 1.73,
    }
}

/// Phase-shift scanners of the FARO Focus and Leica RTC360 class: 300° vertical field of
/// view, millimetre noise, 0.6 m to 150 m.
fn terrestrial() -> Sensor {
    Sensor {
        name: "terrestrial scanner".into(),
        elevations: Elevations::Grid { lowest_deg: -60.0, highest_deg: 90.0 },
        azimuth_step_deg: 0.2,
        sweep_seconds: 120.0,
        min_range: 0.6,
        max_range: 150.0,
        range_noise: 0.002,
        dropout: 0.0,
        mount_height: 1.5,
    }
}

impl FromStr for SensorPreset {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|preset| preset.key() == text).ok_or_else(|| {
            let keys: Vec<&str> = Self::ALL.iter().map(|preset| preset.key()).collect();
            format!("unknown sensor `{text}`; the sensors are {}", keys.join(", "))
        })
    }
}
