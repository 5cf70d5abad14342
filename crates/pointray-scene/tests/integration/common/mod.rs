//! Helpers shared by the integration tests.

use std::path::Path;

use glam::{DVec3, Vec3};
use pointray_io::{PointCloud, TriangleMesh};

/// A sphere of `count` points around `center`, without normals, so that prep computes them.
pub fn sphere_cloud(center: DVec3, radius: f64, count: usize) -> PointCloud {
    let golden = 0.618_033_988_749_894_9_f64;
    let positions = (0..count)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let ring = (1.0 - y * y).sqrt();
            let a = std::f64::consts::TAU * (i as f64 * golden).fract();
            center + DVec3::new(ring * a.cos(), y, ring * a.sin()) * radius
        })
        .collect();
    PointCloud::from_positions(positions)
}

pub fn write_sphere_ply(path: &Path, center: DVec3, count: usize) {
    pointray_io::formats::ply::write_point_cloud(path, &sphere_cloud(center, 1.0, count)).unwrap();
}

/// A tetrahedron with one vertex at each of the given points.
pub fn tetrahedron(points: [Vec3; 4]) -> TriangleMesh {
    TriangleMesh { positions: points.to_vec(), triangles: vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]] }
}

/// Sorted names of the entries of `dir`.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

pub fn assert_close(a: Vec3, b: Vec3, tolerance: f32) {
    assert!((a - b).abs().max_element() <= tolerance, "{a} != {b} (tolerance {tolerance})");
}
