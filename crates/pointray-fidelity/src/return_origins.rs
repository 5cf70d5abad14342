//! Where each return of a scan was seen from.

use glam::DVec3;
use pointray_io::PointCloud;

use crate::FidelityError;

/// The sensor origin of every return: one position for the whole cloud, or one per point
/// (a moving sensor, or several stations merged).
pub enum ReturnOrigins<'a> {
    Fixed(DVec3),
    PerPoint(&'a [DVec3]),
}

impl<'a> ReturnOrigins<'a> {
    /// `position` when given (it overrides what the file says), else the file's per-point
    /// origins, else its one sensor position.
    pub fn of_cloud(cloud: &'a PointCloud, position: Option<DVec3>) -> Result<Self, FidelityError> {
        let origins = match (position, &cloud.sensor_origins, cloud.sensor_position) {
            (Some(position), _, _) => ReturnOrigins::Fixed(position),
            (None, Some(origins), _) if origins.len() != cloud.len() => {
                return Err(FidelityError::SensorOriginCount { origins: origins.len(), points: cloud.len() });
            }
            (None, Some(origins), _) => ReturnOrigins::PerPoint(origins),
            (None, None, Some(position)) => ReturnOrigins::Fixed(position),
            (None, None, None) => return Err(FidelityError::NoSensor),
        };
        if !origins.all_finite() {
            return Err(FidelityError::NonFiniteSensor);
        }
        Ok(origins)
    }

    /// Return `i`'s origin.
    pub fn of(&self, i: usize) -> DVec3 {
        match self {
            ReturnOrigins::Fixed(position) => *position,
            ReturnOrigins::PerPoint(origins) => origins[i],
        }
    }

    /// Where the sensor stood on average.
    pub fn mean(&self) -> DVec3 {
        match self {
            ReturnOrigins::Fixed(position) => *position,
            ReturnOrigins::PerPoint(origins) => origins.iter().sum::<DVec3>() / origins.len().max(1) as f64,
        }
    }

    fn all_finite(&self) -> bool {
        match self {
            ReturnOrigins::Fixed(position) => position.is_finite(),
            ReturnOrigins::PerPoint(origins) => origins.iter().all(|o| o.is_finite()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_explicit_position_wins_then_per_point_origins_then_the_file_s_position() {
        let mut cloud = PointCloud::from_positions(vec![DVec3::X, DVec3::Y]);
        cloud.sensor_position = Some(DVec3::Z);
        assert_eq!(ReturnOrigins::of_cloud(&cloud, None).unwrap().of(1), DVec3::Z);
        cloud.sensor_origins = Some(vec![DVec3::ZERO, DVec3::splat(2.0)]);
        let per_point = ReturnOrigins::of_cloud(&cloud, None).unwrap();
        assert_eq!((per_point.of(1), per_point.mean()), (DVec3::splat(2.0), DVec3::ONE));
        assert_eq!(ReturnOrigins::of_cloud(&cloud, Some(DVec3::NEG_X)).unwrap().of(0), DVec3::NEG_X);
    }

    #[test]
    fn missing_miscounted_or_broken_origins_are_errors() {
        let mut cloud = PointCloud::from_positions(vec![DVec3::X, DVec3::Y]);
        assert!(matches!(ReturnOrigins::of_cloud(&cloud, None), Err(FidelityError::NoSensor)));
        cloud.sensor_origins = Some(vec![DVec3::ZERO]);
        let miscounted = ReturnOrigins::of_cloud(&cloud, None);
        assert!(matches!(miscounted, Err(FidelityError::SensorOriginCount { origins: 1, points: 2 })));
        cloud.sensor_origins = Some(vec![DVec3::ZERO, DVec3::NAN]);
        assert!(matches!(ReturnOrigins::of_cloud(&cloud, None), Err(FidelityError::NonFiniteSensor)));
    }
}
