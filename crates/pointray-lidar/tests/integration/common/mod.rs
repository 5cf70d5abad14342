//! Scenes whose every surface is known, and sensors made exact (no noise).

use glam::{DVec3, Vec3};
use pointray_io::TriangleMesh;
use pointray_lidar::{LidarScene, Sensor, SensorPose, Surface, UpAxis};

/// The inside of a box, `min` to `max`, Z up: every ray from inside it hits.
pub const ROOM_MIN: Vec3 = Vec3::new(-20.0, -15.0, -2.0);
pub const ROOM_MAX: Vec3 = Vec3::new(20.0, 15.0, 8.0);

pub fn room() -> LidarScene {
    let (lo, hi) = (ROOM_MIN, ROOM_MAX);
    let corners: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new(pick(i & 1, lo.x, hi.x), pick(i & 2, lo.y, hi.y), pick(i & 4, lo.z, hi.z)))
        .collect();
    // The six faces by their corner indices (bits: x, y, z).
    let faces = [[0, 2, 6, 4], [1, 3, 7, 5], [0, 1, 5, 4], [2, 3, 7, 6], [0, 1, 3, 2], [4, 5, 7, 6]];
    let mut mesh = TriangleMesh { positions: corners, triangles: Vec::new() };
    for face in faces {
        mesh.push_polygon(&face);
    }
    LidarScene::from_surfaces(&[Surface::new("wall", mesh, 0.5)], UpAxis::Z).unwrap()
}

fn pick(bit: usize, low: f32, high: f32) -> f32 {
    if bit == 0 { low } else { high }
}

/// How far `point` is from the room's nearest face.
pub fn distance_to_room(point: DVec3) -> f64 {
    let (lo, hi) = (ROOM_MIN.as_dvec3(), ROOM_MAX.as_dvec3());
    let inside = (point - lo).min(hi - point);
    inside.abs().min_element()
}

/// A preset with its noise and dropout off and a coarse azimuth step, so that tests are quick
/// and exact.
pub fn exact(preset: pointray_lidar::SensorPreset, azimuth_step_deg: f64) -> Sensor {
    Sensor { range_noise: 0.0, dropout: 0.0, azimuth_step_deg, ..preset.sensor() }
}

pub fn station(x: f64, y: f64, z: f64) -> SensorPose {
    SensorPose { position: DVec3::new(x, y, z), yaw_deg: 0.0 }
}
