//! Re-simulation from real data: the rays of a real sweep cast from a pose into a prepped map,
//! and the ranges they meet set against the ranges the sensor measured.

use glam::{Affine3A, DAffine3, DVec3};
use pointray_io::PointCloud;
use pointray_kernels::{PatchAcceptance, Ray};
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

/// How sensors meet patches, on every caster: inside the box and over the patch's support.
pub const SENSOR_ACCEPTANCE: PatchAcceptance = PatchAcceptance::Disk;

/// Casts rays into a prepped map: the CPU renderer's BVHs (`LidarScene`), or a GPU's
/// (pointray-render opens the one a backend choice names). Rays start at t = 0 and meet
/// patches as `SENSOR_ACCEPTANCE` says.
pub trait MapCaster {
    /// Where the caster's frame has its origin, in the map's coordinates. Poses come in that
    /// frame in f32, which keeps their precision where a map lies far from the origin.
    fn centre(&self) -> DVec3;

    /// The distance to the first surface along each of `rays` (in a sensor's frame, unit
    /// directions) cast from each of `poses` (the sensor's frame into the caster's), pose
    /// after pose, within `max_range`; `None` where it meets none.
    fn cast(&self, rays: &[Ray], poses: &[Affine3A], max_range: f32) -> Result<Vec<Option<f32>>, LidarError>;
}

impl MapCaster for LidarScene {
    fn centre(&self) -> DVec3 {
        LidarScene::centre(self)
    }

    fn cast(&self, rays: &[Ray], poses: &[Affine3A], max_range: f32) -> Result<Vec<Option<f32>>, LidarError> {
        let posed = |i: usize| {
            let (pose, ray) = (&poses[i / rays.len()], &rays[i % rays.len()]);
            Ray::new(pose.transform_point3(ray.origin), pose.transform_vector3(ray.direction).normalize())
        };
        let casts = rays.len() * poses.len();
        Ok((0..casts)
            .into_par_iter()
            .map(|i| self.renderer_hit(&posed(i), max_range).map(|hit| hit.t))
            .collect())
    }
}

/// The rays of `rays` in their sensor's frame, in f32.
pub fn sensor_rays(rays: &SweepRays) -> Vec<Ray> {
    rays.origins.par_iter().zip(&rays.directions).map(|(o, d)| Ray::new(o.as_vec3(), d.as_vec3())).collect()
}

/// `pose` (sensor to map) as a map from the sensor's frame into that of a caster centred at
/// `centre`.
pub fn pose_about(pose: &DAffine3, centre: DVec3) -> Affine3A {
    Affine3A::from_mat3_translation(pose.matrix3.as_mat3(), (pose.translation - centre).as_vec3())
}

/// The range each ray of `rays`, moved by `pose` (sensor to map), meets in the map `caster`
/// casts into, within `max_range`; `None` where it meets nothing.
pub fn resimulate(
    caster: &dyn MapCaster,
    pose: &DAffine3,
    rays: &SweepRays,
    max_range: f64,
) -> Result<Vec<Option<f64>>, LidarError> {
    Ok(resimulate_from(caster, std::slice::from_ref(pose), rays, max_range)?.pop().unwrap_or_default())
}

/// As `resimulate`, from each of `poses` in one cast: a sweep's ranges for each pose.
pub fn resimulate_from(
    caster: &dyn MapCaster,
    poses: &[DAffine3],
    rays: &SweepRays,
    max_range: f64,
) -> Result<Vec<Vec<Option<f64>>>, LidarError> {
    if !(max_range > 0.0 && max_range.is_finite()) {
        return Err(LidarError::invalid("max-range", format!("must be positive, not {max_range}")));
    }
    let centre = caster.centre();
    let poses: Vec<Affine3A> = poses.iter().map(|pose| pose_about(pose, centre)).collect();
    let ranges = caster.cast(&sensor_rays(rays), &poses, max_range as f32)?;
    let sweep = |chunk: &[Option<f32>]| chunk.iter().map(|range| range.map(f64::from)).collect();
    Ok(match rays.ranges.len() {
        0 => vec![Vec::new(); poses.len()],
        rays => ranges.par_chunks(rays).map(sweep).collect(),
    })
}
