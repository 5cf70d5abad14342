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
    /// Per-point LAS classification codes (ASPRS), when the file carries them.
    pub classifications: Option<Vec<u8>>,
    /// Per-point scan line: the beam (ring) of a spinning sensor, or the row of a scanner's
    /// angular grid, when the file carries it. Prep builds neighbourhoods across lines from it.
    pub rings: Option<Vec<u16>>,
    /// Per-point sensor positions, when the cloud merges several stations or a moving sensor;
    /// they take precedence over `sensor_position`.
    pub sensor_origins: Option<Vec<DVec3>>,
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

    /// Where point `i` was seen from, when the file says so.
    pub fn sensor_of(&self, i: usize) -> Option<DVec3> {
        self.sensor_origins.as_ref().map(|origins| origins[i]).or(self.sensor_position)
    }
}
