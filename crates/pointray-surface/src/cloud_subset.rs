//! A cloud's chosen points with every attribute they carry, and two clouds joined.

use pointray_io::PointCloud;

/// The points `indices` of `cloud`, in that order, with their attributes.
pub(crate) fn subset(cloud: &PointCloud, indices: &[u32]) -> PointCloud {
    fn pick<T: Copy>(values: &Option<Vec<T>>, indices: &[u32]) -> Option<Vec<T>> {
        values.as_ref().map(|values| indices.iter().map(|&i| values[i as usize]).collect())
    }
    PointCloud {
        positions: indices.iter().map(|&i| cloud.positions[i as usize]).collect(),
        normals: pick(&cloud.normals, indices),
        colors: pick(&cloud.colors, indices),
        intensities: pick(&cloud.intensities, indices),
        classifications: pick(&cloud.classifications, indices),
        rings: pick(&cloud.rings, indices),
        sensor_origins: pick(&cloud.sensor_origins, indices),
        sensor_position: cloud.sensor_position,
    }
}

/// `first`'s points followed by `second`'s (which carries the same attributes).
pub(crate) fn concatenated(mut first: PointCloud, second: PointCloud) -> PointCloud {
    first.append(second);
    first
}
