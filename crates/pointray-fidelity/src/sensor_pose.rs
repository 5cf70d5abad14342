//! Where a scan's sensor stood and which elevations its beams swept: what the sensor views
//! need from the points file.

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;

use crate::FidelityError;
use crate::return_origins::ReturnOrigins;

/// A sensor of a scan, in the cloud's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorPose {
    pub position: Vec3,
    /// The lowest and highest elevation in degrees, above the plane normal to the up axis, of
    /// any return seen from its own sensor origin.
    pub elevation_degrees: [f32; 2],
    /// The farthest return from its own sensor origin.
    pub max_range: f32,
}

impl SensorPose {
    /// The sensor at `position`, or else where the cloud says it stood (the mean of the
    /// per-point origins of a moving sensor or merged stations). `up` is the scan's up axis.
    pub fn of_cloud(cloud: &PointCloud, up: Vec3, position: Option<DVec3>) -> Result<Self, FidelityError> {
        let origins = ReturnOrigins::of_cloud(cloud, position)?;
        let up = up.as_dvec3().try_normalize().ok_or(FidelityError::InvalidUp(up))?;
        let rays = cloud.positions.iter().enumerate().filter_map(|(i, &p)| {
            let ray = p - origins.of(i);
            let range = ray.length();
            (range > 0.0 && range.is_finite())
                .then(|| ((ray.dot(up) / range).clamp(-1.0, 1.0).asin().to_degrees(), range))
        });
        let (low, high, max_range) = rays.fold(
            (f64::INFINITY, f64::NEG_INFINITY, 0.0),
            |(lo, hi, far): (f64, f64, f64), (elevation, range)| {
                (lo.min(elevation), hi.max(elevation), far.max(range))
            },
        );
        if low >= high {
            return Err(FidelityError::NoElevationBand);
        }
        Ok(Self {
            position: origins.mean().as_vec3(),
            elevation_degrees: [low as f32, high as f32],
            max_range: max_range as f32,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_band_spans_the_returns_seen_from_the_sensor() {
        let mut cloud = PointCloud::from_positions(vec![
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(0.0, 10.0, 12.0),
            DVec3::new(-10.0, 0.0, 2.0 - 10.0),
        ]);
        cloud.sensor_position = Some(DVec3::new(0.0, 0.0, 2.0));
        let pose = SensorPose::of_cloud(&cloud, Vec3::Z, None).unwrap();
        assert_eq!(pose.position, Vec3::new(0.0, 0.0, 2.0));
        let [low, high] = pose.elevation_degrees;
        assert!((low + 45.0).abs() < 1e-4 && (high - 45.0).abs() < 1e-4, "{low} {high}");
        assert!((pose.max_range - 200f32.sqrt()).abs() < 1e-4, "{}", pose.max_range);
        // An explicit position wins over the file's.
        let moved = SensorPose::of_cloud(&cloud, Vec3::Z, Some(DVec3::new(0.0, 0.0, 12.0))).unwrap();
        assert_eq!(moved.position.z, 12.0);
        assert!(moved.elevation_degrees[1] < 1e-4, "{:?}", moved.elevation_degrees);
    }

    #[test]
    fn per_point_origins_set_the_position_and_each_point_s_elevation() {
        let mut cloud =
            PointCloud::from_positions(vec![DVec3::new(10.0, 0.0, 10.0), DVec3::new(20.0, 0.0, 0.0)]);
        cloud.sensor_origins = Some(vec![DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0)]);
        let pose = SensorPose::of_cloud(&cloud, Vec3::Z, None).unwrap();
        assert_eq!(pose.position, Vec3::new(5.0, 0.0, 0.0));
        let [low, high] = pose.elevation_degrees;
        assert!(low.abs() < 1e-4 && (high - 45.0).abs() < 1e-4, "{low} {high}");
    }

    #[test]
    fn no_sensor_or_a_flat_band_is_an_error() {
        let cloud = PointCloud::from_positions(vec![DVec3::X, DVec3::Y]);
        assert!(matches!(SensorPose::of_cloud(&cloud, Vec3::Z, None), Err(FidelityError::NoSensor)));
        let flat = SensorPose::of_cloud(&cloud, Vec3::Z, Some(DVec3::ZERO));
        assert!(matches!(flat, Err(FidelityError::NoElevationBand)));
    }
}
