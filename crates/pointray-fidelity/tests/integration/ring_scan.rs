//! Synthetic scans: a spinning sensor's rings over flat ground, built in code.

use glam::DVec3;
use pointray_io::PointCloud;

/// The sensor stands 2 above the ground z = 0.
pub const SENSOR: DVec3 = DVec3::new(0.0, 0.0, 2.0);
/// Beam elevations in degrees, one ring per degree: the ground from 2.4 to 9.4 away.
pub const LOWEST_BEAM: i32 = -40;
pub const HIGHEST_BEAM: i32 = -12;
/// Azimuth step in degrees.
const AZIMUTH_STEP: usize = 2;

/// The unit direction of a beam at `elevation` and `azimuth`, in degrees.
pub fn beam(elevation: f64, azimuth: f64) -> DVec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
}

/// Every beam's return from the ground, with its ring and the sensor position.
pub fn ground_scan() -> PointCloud {
    let mut positions = Vec::new();
    let mut rings = Vec::new();
    for (ring, elevation) in (LOWEST_BEAM..=HIGHEST_BEAM).enumerate() {
        for azimuth in (0..360).step_by(AZIMUTH_STEP) {
            let direction = beam(f64::from(elevation), azimuth as f64);
            positions.push(SENSOR + direction * (SENSOR.z / -direction.z));
            rings.push(ring as u16);
        }
    }
    let mut cloud = PointCloud::from_positions(positions);
    cloud.rings = Some(rings);
    cloud.sensor_position = Some(SENSOR);
    cloud
}

/// `cloud` without the points `drop` picks (rings kept in step).
pub fn without(cloud: &PointCloud, drop: impl Fn(DVec3) -> bool) -> PointCloud {
    let keep: Vec<usize> = (0..cloud.len()).filter(|&i| !drop(cloud.positions[i])).collect();
    let mut kept = PointCloud::from_positions(keep.iter().map(|&i| cloud.positions[i]).collect());
    kept.rings = cloud.rings.as_ref().map(|rings| keep.iter().map(|&i| rings[i]).collect());
    kept.sensor_position = cloud.sensor_position;
    kept
}
