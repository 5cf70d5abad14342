//! What a scan records per point, and what it counts.

use glam::DVec3;
use pointray_io::PointCloud;

use crate::Classification;

/// One return, in the scene's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Return {
    pub position: DVec3,
    /// Reflectance times the cosine of the incidence angle, in [0, 1].
    pub intensity: f32,
    /// The beam (spinning sensors) or the row of the angular grid (terrestrial), 0 lowest.
    pub ring: u16,
    /// The column's angle in radians, counterclockwise from the sensor's forward axis, in
    /// [0, 2π).
    pub azimuth: f32,
    /// Seconds since the first station's sweep began.
    pub time: f32,
    pub classification: Classification,
    /// Where the sensor stood.
    pub sensor: DVec3,
}

/// Where the rays of a scan went.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScanStats {
    pub rays: u64,
    pub returns: u64,
    /// Rays that met nothing within the maximum range.
    pub misses: u64,
    /// Returns lost to the dropout probability.
    pub dropped: u64,
    /// Returns whose measured (noisy) range fell outside the minimum or maximum range.
    pub out_of_range: u64,
}

impl std::ops::AddAssign for ScanStats {
    fn add_assign(&mut self, other: Self) {
        self.rays += other.rays;
        self.returns += other.returns;
        self.misses += other.misses;
        self.dropped += other.dropped;
        self.out_of_range += other.out_of_range;
    }
}

/// The returns as a cloud: positions, intensities, classes, rings and sensor origins.
pub fn to_point_cloud(returns: &[Return]) -> PointCloud {
    PointCloud {
        positions: returns.iter().map(|r| r.position).collect(),
        intensities: Some(returns.iter().map(|r| r.intensity).collect()),
        classifications: Some(returns.iter().map(|r| r.classification.0).collect()),
        rings: Some(returns.iter().map(|r| r.ring).collect()),
        sensor_origins: Some(returns.iter().map(|r| r.sensor).collect()),
        ..PointCloud::default()
    }
}
