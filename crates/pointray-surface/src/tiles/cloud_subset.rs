//! A cloud's chosen points with every attribute they carry.

use pointray_io::PointCloud;

use crate::prep::gather;

/// The points `indices` of `cloud`, in that order, with their attributes.
pub(crate) fn subset(cloud: &PointCloud, indices: &[u32]) -> PointCloud {
    fn pick<T: Copy + Send + Sync>(values: &Option<Vec<T>>, indices: &[u32]) -> Option<Vec<T>> {
        values.as_ref().map(|values| gather(values, indices))
    }
    PointCloud {
        positions: gather(&cloud.positions, indices),
        normals: pick(&cloud.normals, indices),
        colors: pick(&cloud.colors, indices),
        intensities: pick(&cloud.intensities, indices),
        classifications: pick(&cloud.classifications, indices),
        rings: pick(&cloud.rings, indices),
        sensor_origins: pick(&cloud.sensor_origins, indices),
        sensor_position: cloud.sensor_position,
    }
}
