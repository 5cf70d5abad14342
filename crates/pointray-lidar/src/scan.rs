//! Casting a sensor's rays from each station: the first hit of each ray, its range perturbed
//! by Gaussian noise, then thinned by dropout and the range limits.
//!
//! Each column of each station draws its random numbers from its own ChaCha8 stream of the
//! seed, and every ray draws the same amount whether it hits or not, so a seed gives the same
//! scan on any number of threads, and changing one ray's surface moves no other ray's noise.

use std::f64::consts::TAU;

use glam::DVec3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::pose::SensorAxes;
use crate::{LidarError, LidarScene, Return, ScanStats, Sensor, SensorPose};

/// Told how many of the scan's columns (one azimuth of one station) are done.
pub trait ScanProgress: Sync {
    fn columns_done(&self, count: u64);
}

/// No progress to show.
pub struct NoProgress;

impl ScanProgress for NoProgress {
    fn columns_done(&self, _count: u64) {}
}

/// The returns of every station, station by station, column by column, ring by ring.
pub struct Scan {
    pub returns: Vec<Return>,
    pub stats: ScanStats,
}

/// One column: its station, its azimuth and what its rays share.
struct Column<'a> {
    sensor: &'a Sensor,
    elevations: &'a [f64],
    axes: SensorAxes,
    origin: DVec3,
    azimuth: f64,
    time: f64,
}

/// Scans `scene` from every station with one sweep of `sensor`, the stations' sweeps one
/// after the other in time. Every setting is checked first.
pub fn scan(
    scene: &LidarScene,
    sensor: &Sensor,
    stations: &[SensorPose],
    seed: u64,
    progress: &dyn ScanProgress,
) -> Result<Scan, LidarError> {
    check_request(sensor, stations)?;
    let elevations: Vec<f64> = sensor.elevations_deg().iter().map(|e| e.to_radians()).collect();
    let columns = u64::from(sensor.columns());
    let scanned: Vec<(Vec<Return>, ScanStats)> = (0..stations.len() as u64 * columns)
        .into_par_iter()
        .map(|index| {
            let (station, column) = ((index / columns) as usize, index % columns);
            let pose = &stations[station];
            let azimuth = (column as f64 * sensor.azimuth_step_deg).to_radians();
            let column_rays = Column {
                sensor,
                elevations: &elevations,
                axes: SensorAxes::new(scene.up(), pose.yaw_deg),
                origin: pose.position,
                azimuth,
                time: (station as f64 + azimuth / TAU) * sensor.sweep_seconds,
            };
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(index);
            let result = column_rays.cast(scene, &mut rng);
            progress.columns_done(1);
            result
        })
        .collect();
    let mut scan = Scan { returns: Vec::new(), stats: ScanStats::default() };
    scan.returns.reserve(scanned.iter().map(|(returns, _)| returns.len()).sum());
    for (returns, stats) in scanned {
        scan.returns.extend(returns);
        scan.stats += stats;
    }
    Ok(scan)
}

fn check_request(sensor: &Sensor, stations: &[SensorPose]) -> Result<(), LidarError> {
    sensor.validate()?;
    if stations.is_empty() {
        return Err(LidarError::invalid("stations", "a scan needs at least one station"));
    }
    let position_flag = if stations.len() > 1 { "stations" } else { "position" };
    for (index, pose) in stations.iter().enumerate() {
        if !pose.position.is_finite() {
            let problem = format!("station {index} must stand at a finite position, not {}", pose.position);
            return Err(LidarError::invalid(position_flag, problem));
        }
        if !pose.yaw_deg.is_finite() {
            return Err(LidarError::invalid("yaw", format!("must be finite, got {}", pose.yaw_deg)));
        }
    }
    let rays = sensor.rays_per_sweep().saturating_mul(stations.len() as u64);
    let limit = crate::sensor::MAX_RAYS;
    if rays > limit {
        return Err(LidarError::TooManyRays { rays, limit });
    }
    Ok(())
}

impl Column<'_> {
    fn cast(&self, scene: &LidarScene, rng: &mut ChaCha8Rng) -> (Vec<Return>, ScanStats) {
        let sensor = self.sensor;
        let mut returns = Vec::with_capacity(self.elevations.len());
        let mut stats = ScanStats { rays: self.elevations.len() as u64, ..ScanStats::default() };
        for (ring, &elevation) in self.elevations.iter().enumerate() {
            let (dropout_draw, noise) = (rng.random::<f64>(), standard_normal(rng));
            let direction = self.axes.direction(elevation, self.azimuth);
            let Some(hit) = scene.first_hit(self.origin, direction, sensor.max_range) else {
                stats.misses += 1;
                continue;
            };
            if dropout_draw < sensor.dropout {
                stats.dropped += 1;
                continue;
            }
            let range = hit.range + sensor.range_noise * noise;
            if !(sensor.min_range..=sensor.max_range).contains(&range) {
                stats.out_of_range += 1;
                continue;
            }
            returns.push(Return {
                position: self.origin + direction * range,
                intensity: (f64::from(hit.reflectance) * hit.cos_incidence) as f32,
                ring: ring as u16,
                azimuth: self.azimuth as f32,
                time: self.time as f32,
                classification: hit.class,
                sensor: self.origin,
            });
        }
        stats.returns = returns.len() as u64;
        (returns, stats)
    }
}

/// A standard normal deviate (Box–Muller), from two uniform draws.
fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    // 1 - u lies in (0, 1], so its logarithm is finite.
    let radius = (-2.0 * (1.0 - rng.random::<f64>()).ln()).sqrt();
    radius * (TAU * rng.random::<f64>()).cos()
}
