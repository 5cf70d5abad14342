//! Returns from a wall at a known distance lie on it, within the range noise, with the
//! intensity of their incidence angle.

use glam::{DVec3, Vec3};
use pointray_io::TriangleMesh;
use pointray_lidar::{Classification, LidarScene, NoProgress, SensorPreset, Surface, UpAxis, scan};

use crate::common::*;

const WALL_X: f64 = 10.0;
const REFLECTANCE: f32 = 0.6;

/// The plane x = WALL_X, 100 m across.
fn wall() -> LidarScene {
    let x = WALL_X as f32;
    let corner = |y: f32, z: f32| Vec3::new(x, y, z);
    let positions = vec![corner(-50.0, -50.0), corner(50.0, -50.0), corner(50.0, 50.0), corner(-50.0, 50.0)];
    let mesh = TriangleMesh { positions, triangles: vec![[0, 1, 2], [0, 2, 3]] };
    LidarScene::from_surfaces(&[Surface::new("wall", mesh, REFLECTANCE)], UpAxis::Z).unwrap()
}

#[test]
fn exact_returns_lie_on_the_plane_with_lambertian_intensity() {
    let sensor = exact(SensorPreset::Vlp16, 5.0);
    let scanned = scan(&wall(), &sensor, &[station(0.0, 0.0, 0.0)], 1, &NoProgress).unwrap();
    // Columns within ±84° of the wall's normal reach it inside 100 m.
    assert!(scanned.returns.len() > 16 * 30, "only {} returns", scanned.returns.len());
    for r in &scanned.returns {
        assert!((r.position.x - WALL_X).abs() < 1e-4, "{} is off the plane", r.position);
        let direction = (r.position - r.sensor).normalize();
        // The wall's normal is −X, so the cosine of incidence is the direction's x.
        let expected = f64::from(REFLECTANCE) * direction.x;
        assert!((f64::from(r.intensity) - expected).abs() < 1e-4, "intensity {} vs {expected}", r.intensity);
        assert_eq!(r.classification, Classification::BUILDING);
    }
}

#[test]
fn noisy_returns_lie_on_the_plane_within_the_noise() {
    let sigma = 0.02;
    let sensor = pointray_lidar::Sensor { range_noise: sigma, ..exact(SensorPreset::Vlp16, 2.0) };
    let origin = DVec3::new(0.0, 1.0, 0.5);
    let stations = [pointray_lidar::SensorPose { position: origin, yaw_deg: 20.0 }];
    let scanned = scan(&wall(), &sensor, &stations, 3, &NoProgress).unwrap();
    let errors: Vec<f64> = scanned
        .returns
        .iter()
        .map(|r| {
            let offset = r.position - origin;
            let direction = offset.normalize();
            offset.length() - (WALL_X - origin.x) / direction.x
        })
        .collect();
    assert!(errors.len() > 1000, "only {} returns", errors.len());
    assert!(errors.iter().all(|e| e.abs() < 6.0 * sigma), "a range error beyond 6 sigma");
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
    assert!(mean.abs() < 0.2 * sigma, "biased noise: mean {mean}");
    assert!((rms / sigma - 1.0).abs() < 0.1, "the noise's spread is {rms}, not {sigma}");
}
