//! A scanner as a grid of rays: one row (a ring) per elevation angle, one column per azimuth
//! step around the vertical axis, fired once per sweep. Spinning automotive sensors and
//! static terrestrial scanners differ only in their angles and defaults (`presets.rs`).

use crate::LidarError;

/// Past this many rays a scan would take many minutes and gigabytes.
pub const MAX_RAYS: u64 = 100_000_000;

/// The elevation angles of a sensor's rings.
#[derive(Clone, Debug, PartialEq)]
pub enum Elevations {
    /// One angle per beam in degrees above the horizontal, lowest first: ring `i` fires at
    /// the `i`-th angle (as the ROS Velodyne driver numbers rings).
    Beams(Vec<f64>),
    /// A terrestrial scanner's rows: from `lowest_deg` up to, not including, `highest_deg`,
    /// spaced as the azimuth columns are, so that the angular grid is square.
    Grid { lowest_deg: f64, highest_deg: f64 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Sensor {
    /// Its model, for messages and the output's header.
    pub name: String,
    pub elevations: Elevations,
    /// The angle between consecutive columns, in degrees.
    pub azimuth_step_deg: f64,
    /// One full turn; a column fires at `azimuth / 360°` of it.
    pub sweep_seconds: f64,
    /// Returns nearer than this are discarded (the sensor's blind zone, the car it sits on).
    pub min_range: f64,
    /// Surfaces beyond this give no return.
    pub max_range: f64,
    /// The standard deviation of the Gaussian error added to each range.
    pub range_noise: f64,
    /// The probability that a return is lost.
    pub dropout: f64,
    /// How high above the ground the sensor is mounted by default (a car's roof, a tripod).
    pub mount_height: f64,
}

/// Spinning sensors take uniform beam tables from their data sheets' extreme angles.
pub fn uniform_beams(count: usize, lowest_deg: f64, highest_deg: f64) -> Vec<f64> {
    let spacing = (highest_deg - lowest_deg) / (count.max(2) - 1) as f64;
    (0..count).map(|i| lowest_deg + i as f64 * spacing).collect()
}

impl Sensor {
    /// Each ring's elevation in degrees, lowest first.
    pub fn elevations_deg(&self) -> Vec<f64> {
        match &self.elevations {
            Elevations::Beams(angles) => angles.clone(),
            &Elevations::Grid { lowest_deg, .. } => {
                (0..self.ring_count()).map(|row| lowest_deg + row as f64 * self.azimuth_step_deg).collect()
            }
        }
    }

    /// How many rings (rows) the sensor has, without listing them.
    pub fn ring_count(&self) -> u64 {
        match &self.elevations {
            Elevations::Beams(angles) => angles.len() as u64,
            &Elevations::Grid { lowest_deg, highest_deg } => {
                ((highest_deg - lowest_deg) / self.azimuth_step_deg - 1e-9).ceil().max(0.0) as u64
            }
        }
    }

    /// Columns per sweep: azimuths `0, step, 2 step, …` below 360°.
    pub fn columns(&self) -> u32 {
        (360.0 / self.azimuth_step_deg - 1e-9).ceil().max(1.0) as u32
    }

    pub fn rays_per_sweep(&self) -> u64 {
        self.ring_count().saturating_mul(u64::from(self.columns()))
    }

    /// Checks every setting, naming the first that is out of range.
    pub fn validate(&self) -> Result<(), LidarError> {
        let step = self.azimuth_step_deg;
        if !(step.is_finite() && step > 0.0 && step <= 360.0) {
            return Err(LidarError::invalid(
                "azimuth-step",
                format!("must be in (0, 360] degrees, got {step}"),
            ));
        }
        let rays = self.rays_per_sweep();
        if rays > MAX_RAYS {
            return Err(LidarError::TooManyRays { rays, limit: MAX_RAYS });
        }
        self.validate_elevations()?;
        self.validate_ranges()?;
        let dropout = self.dropout;
        if !(0.0..1.0).contains(&dropout) {
            let problem =
                format!("must be a probability in [0, 1) (1 would drop every return), got {dropout}");
            return Err(LidarError::invalid("dropout", problem));
        }
        if !(self.sweep_seconds.is_finite() && self.sweep_seconds > 0.0) {
            let problem = format!("its sweep must last a positive time, not {} s", self.sweep_seconds);
            return Err(LidarError::invalid("sensor", problem));
        }
        Ok(())
    }

    fn validate_ranges(&self) -> Result<(), LidarError> {
        let (min, max, noise) = (self.min_range, self.max_range, self.range_noise);
        if !(min.is_finite() && min >= 0.0) {
            return Err(LidarError::invalid(
                "min-range",
                format!("must be finite and at least 0, got {min}"),
            ));
        }
        if !(max.is_finite() && max > min) {
            let problem = format!("must be finite and beyond the minimum range {min}, got {max}");
            return Err(LidarError::invalid("max-range", problem));
        }
        if !(noise.is_finite() && noise >= 0.0 && noise < max) {
            let problem = format!(
                "the range noise's sigma must be at least 0 and below the maximum range {max}, got {noise}"
            );
            return Err(LidarError::invalid("noise", problem));
        }
        Ok(())
    }

    fn validate_elevations(&self) -> Result<(), LidarError> {
        let rings = self.ring_count();
        if rings == 0 {
            return Err(LidarError::invalid("sensor", "it has no rings"));
        }
        if rings > u64::from(u16::MAX) + 1 {
            return Err(LidarError::invalid(
                "sensor",
                format!("{rings} rings do not fit the 16-bit ring index"),
            ));
        }
        let angles = self.elevations_deg();
        if let Some(bad) = angles.iter().find(|a| !(a.is_finite() && (-90.0..=90.0).contains(*a))) {
            return Err(LidarError::invalid("sensor", format!("elevation {bad}° is outside [-90°, 90°]")));
        }
        if angles.windows(2).any(|pair| pair[1] <= pair[0]) {
            return Err(LidarError::invalid("sensor", "ring elevations must rise strictly from ring 0"));
        }
        Ok(())
    }
}
