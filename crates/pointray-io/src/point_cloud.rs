//! A point set as read from a file, before any processing.

use glam::{DVec3, Vec3};

/// Positions stay in f64 until `prep` recentres them, so that geo-referenced scans
/// (coordinates near 10^6) keep their precision.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointCloud {
    pub positions: Vec<DVec3>,
    /// Per-point normals, when the file carries them (not necessarily unit length).
    pub normals: Option<Vec<Vec3>>,
    /// Per-point sRGB colours, when the file carries them.
    pub colors: Option<Vec<[u8; 3]>>,
    /// Per-point intensities normalised to [0, 1], when the file carries them.
    pub intensities: Option<Vec<f32>>,
    /// Where the scanner stood, when the file says so; normals are oriented toward it.
    pub sensor_position: Option<DVec3>,
}

impl PointCloud {
    pub fn from_positions(positions: Vec<DVec3>) -> Self {
        Self { positions, ..Self::default() }
    }

    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}
