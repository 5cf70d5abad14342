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

    /// The bytes each point's attributes (all but its position) take in memory: what a
    /// cloud held through a whole prep costs beyond the prep itself.
    pub fn attribute_bytes_per_point(&self) -> u64 {
        AttributeBytes {
            normals: self.normals.is_some(),
            colors: self.colors.is_some(),
            intensities: self.intensities.is_some(),
            classifications: self.classifications.is_some(),
            rings: self.rings.is_some(),
            sensor_origins: self.sensor_origins.is_some(),
        }
        .per_point()
    }

    /// Appends the points of `other`, a cloud with the same attributes (the next chunk of the
    /// same file, say).
    pub fn append(&mut self, other: PointCloud) {
        fn join<T>(into: &mut Option<Vec<T>>, from: Option<Vec<T>>) {
            if let (Some(into), Some(from)) = (into.as_mut(), from) {
                into.extend(from);
            }
        }
        self.positions.extend(other.positions);
        join(&mut self.normals, other.normals);
        join(&mut self.colors, other.colors);
        join(&mut self.intensities, other.intensities);
        join(&mut self.classifications, other.classifications);
        join(&mut self.rings, other.rings);
        join(&mut self.sensor_origins, other.sensor_origins);
    }

    /// Where point `i` was seen from, when the file says so.
    pub fn sensor_of(&self, i: usize) -> Option<DVec3> {
        self.sensor_origins.as_ref().map(|origins| origins[i]).or(self.sensor_position)
    }
}

/// Which per-point attributes a cloud carries, for what they cost in memory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AttributeBytes {
    pub normals: bool,
    pub colors: bool,
    pub intensities: bool,
    pub classifications: bool,
    pub rings: bool,
    pub sensor_origins: bool,
}

impl AttributeBytes {
    /// The bytes a point's attributes take in a `PointCloud`.
    pub fn per_point(self) -> u64 {
        [
            (self.normals, size_of::<Vec3>()),
            (self.colors, size_of::<[u8; 3]>()),
            (self.intensities, size_of::<f32>()),
            (self.classifications, size_of::<u8>()),
            (self.rings, size_of::<u16>()),
            (self.sensor_origins, size_of::<DVec3>()),
        ]
        .iter()
        .filter(|(present, _)| *present)
        .map(|(_, bytes)| *bytes as u64)
        .sum()
    }
}
