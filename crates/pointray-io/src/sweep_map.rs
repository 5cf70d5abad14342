//! Several sweeps, each with its sensor pose, as one cloud in the map's frame. Each return
//! keeps its sweep's sensor origin and its line, so that prep builds scan-aware patches per
//! sweep: a sweep is one station of the scan's structure.

use std::path::Path;

use glam::{DAffine3, DVec3};

use crate::{IoError, PointCloud};

/// Joins `sweeps` (each in its sensor's frame) placed by `poses` (sensor to map).
/// `names` name the sweeps in errors.
pub fn sweep_map(
    mut sweeps: Vec<PointCloud>,
    poses: &[DAffine3],
    names: &[&Path],
) -> Result<PointCloud, IoError> {
    keep_shared_attributes(&mut sweeps);
    let mut map: Option<PointCloud> = None;
    for ((sweep, pose), name) in sweeps.into_iter().zip(poses).zip(names) {
        let placed = placed(sweep, pose, name)?;
        match map.as_mut() {
            Some(map) => map.append(placed),
            None => map = Some(placed),
        }
    }
    map.ok_or_else(|| IoError::malformed("", "a map needs at least one sweep"))
}

/// Drops each attribute that not every sweep carries: a map's attributes cover all its points.
fn keep_shared_attributes(sweeps: &mut [PointCloud]) {
    fn shared<T>(sweeps: &mut [PointCloud], field: fn(&mut PointCloud) -> &mut Option<T>) {
        if sweeps.iter_mut().any(|sweep| field(sweep).is_none()) {
            sweeps.iter_mut().for_each(|sweep| *field(sweep) = None);
        }
    }
    shared(sweeps, |s| &mut s.normals);
    shared(sweeps, |s| &mut s.colors);
    shared(sweeps, |s| &mut s.intensities);
    shared(sweeps, |s| &mut s.classifications);
    shared(sweeps, |s| &mut s.rings);
}

/// One sweep moved into the map, with its sensor's map position on every return.
fn placed(sweep: PointCloud, pose: &DAffine3, name: &Path) -> Result<PointCloud, IoError> {
    let sensor = pose.transform_point3(sweep.sensor_position.unwrap_or(DVec3::ZERO));
    let positions: Vec<DVec3> = sweep.positions.iter().map(|&p| pose.transform_point3(p)).collect();
    if !sensor.is_finite() {
        return Err(IoError::malformed(name, "its pose places the sensor at a non-finite position"));
    }
    let normals = sweep
        .normals
        .map(|normals| normals.iter().map(|&n| pose.transform_vector3(n.as_dvec3()).as_vec3()).collect());
    let sensor_origins = match sweep.sensor_origins {
        Some(origins) => origins.iter().map(|&o| pose.transform_point3(o)).collect(),
        None => vec![sensor; positions.len()],
    };
    Ok(PointCloud {
        positions,
        normals,
        sensor_origins: Some(sensor_origins),
        sensor_position: None,
        ..sweep
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(rings: bool) -> PointCloud {
        PointCloud {
            positions: vec![DVec3::X, DVec3::Y],
            rings: rings.then(|| vec![0, 1]),
            sensor_position: Some(DVec3::Z),
            ..PointCloud::default()
        }
    }

    #[test]
    fn each_sweep_keeps_its_sensor_in_the_map() {
        let poses = [DAffine3::IDENTITY, DAffine3::from_translation(DVec3::new(5.0, 0.0, 0.0))];
        let map =
            sweep_map(vec![sweep(true), sweep(true)], &poses, &[Path::new("a"), Path::new("b")]).unwrap();
        assert_eq!(map.positions[2], DVec3::new(6.0, 0.0, 0.0));
        assert_eq!(map.sensor_of(0), Some(DVec3::Z));
        assert_eq!(map.sensor_of(3), Some(DVec3::new(5.0, 0.0, 1.0)));
        assert_eq!(map.rings.as_deref(), Some(&[0, 1, 0, 1][..]));
    }

    #[test]
    fn lines_are_kept_only_when_every_sweep_has_them() {
        let poses = [DAffine3::IDENTITY; 2];
        let map =
            sweep_map(vec![sweep(true), sweep(false)], &poses, &[Path::new("a"), Path::new("b")]).unwrap();
        assert!(map.rings.is_none());
    }
}
