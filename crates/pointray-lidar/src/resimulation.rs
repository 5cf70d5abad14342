//! Re-simulation from real data: the rays of a real sweep cast from a pose into a prepped map,
//! and the ranges they meet set against the ranges the sensor measured.

use glam::{DAffine3, DVec3};
use pointray_io::PointCloud;
use rayon::prelude::*;

use crate::{LidarError, LidarScene};

/// The rays of a sweep in its sensor's frame: their origin (the sensor), unit directions and
/// the ranges the sensor measured along them.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRays {
    pub origin: DVec3,
    pub directions: Vec<DVec3>,
    pub ranges: Vec<f64>,
}

impl SweepRays {
    /// The rays of a sweep read in its sensor's frame; returns at the sensor itself have no
    /// direction and are left out.
    pub fn of_sweep(sweep: &PointCloud) -> Self {
        let origin = sweep.sensor_position.unwrap_or(DVec3::ZERO);
        let (directions, ranges) = sweep
            .positions
            .iter()
            .map(|&p| p - origin)
            .filter(|offset| offset.length() > 0.0 && offset.is_finite())
            .map(|offset| (offset.normalize(), offset.length()))
            .unzip();
        Self { origin, directions, ranges }
    }

    /// Where the measured returns lie in the sensor's frame.
    pub fn measured_points(&self) -> Vec<DVec3> {
        self.directions.iter().zip(&self.ranges).map(|(&d, &r)| self.origin + d * r).collect()
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
    let origin = pose.transform_point3(rays.origin);
    Ok(rays
        .directions
        .par_iter()
        .map(|&direction| {
            let direction = pose.transform_vector3(direction).normalize();
            scene.first_hit(origin, direction, max_range).map(|hit| hit.range)
        })
        .collect())
}
