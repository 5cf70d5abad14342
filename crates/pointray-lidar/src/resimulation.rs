//! Re-simulation from real data: the rays of a real sweep cast from a pose into a prepped map,
//! and the ranges they meet set against the ranges the sensor measured.

use glam::{DAffine3, DVec3};
use pointray_io::PointCloud;
use rayon::prelude::*;

use crate::{LidarError, LidarScene};

/// The rays of a sweep in its sensor's frame: where each starts (its laser's origin), unit
/// directions and the ranges the sensor measured along them.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRays {
    pub origins: Vec<DVec3>,
    pub directions: Vec<DVec3>,
    pub ranges: Vec<f64>,
}

impl SweepRays {
    /// The rays of a sweep read in its sensor's frame, each from its return's own sensor
    /// origin (a multi-block head's laser block); returns at their origin have no direction
    /// and are left out.
    pub fn of_sweep(sweep: &PointCloud) -> Self {
        let mut rays = Self { origins: Vec::new(), directions: Vec::new(), ranges: Vec::new() };
        for (i, &position) in sweep.positions.iter().enumerate() {
            let origin = sweep.sensor_of(i).unwrap_or(DVec3::ZERO);
            let offset = position - origin;
            if offset.length() > 0.0 && offset.is_finite() {
                rays.origins.push(origin);
                rays.directions.push(offset.normalize());
                rays.ranges.push(offset.length());
            }
        }
        rays
    }

    /// Where ray `i` lies at `range`, in the sensor's frame.
    pub fn point(&self, i: usize, range: f64) -> DVec3 {
        self.origins[i] + self.directions[i] * range
    }
}

/// The range each ray of `rays`, moved by `pose` (sensor to map), meets in `scene` within
/// `max_range`; `None` where it meets nothing.
pub fn resimulate(
    scene: &LidarScene,
    pose: &DAffine3,
    rays: &SweepRays,
    max_range: f64,
) -> Result<Vec<Option<f64>>, LidarError> {
    if !(max_range > 0.0 && max_range.is_finite()) {
        return Err(LidarError::invalid("max-range", format!("must be positive, not {max_range}")));
    }
    Ok(rays
        .origins
        .par_iter()
        .zip(&rays.directions)
        .map(|(&origin, &direction)| {
            let (origin, direction) =
                (pose.transform_point3(origin), pose.transform_vector3(direction).normalize());
            scene.first_hit(origin, direction, max_range).map(|hit| hit.range)
        })
        .collect())
}
