//! Procedural point sets lie on their surfaces, carry outward unit normals and are spread
//! evenly by area.

use glam::{DVec3, Vec3};
use pointray_scene::procedural::{sphere_points, torus_points};

fn fraction(points: &[DVec3], test: impl Fn(DVec3) -> bool) -> f64 {
    points.iter().filter(|p| test(**p)).count() as f64 / points.len() as f64
}

#[test]
fn sphere_points_are_on_the_sphere_and_evenly_spread() {
    let center = Vec3::new(1.0, -2.0, 0.5);
    let cloud = sphere_points(center, 2.0, 10_000);
    let center = center.as_dvec3();
    let normals = cloud.normals.as_ref().unwrap();
    for (p, n) in cloud.positions.iter().zip(normals) {
        assert!(((*p - center).length() - 2.0).abs() < 1e-5);
        assert!((n.length() - 1.0).abs() < 1e-5);
        assert!((*p - center).normalize().as_vec3().dot(*n) > 0.9999, "outward");
    }
    // A cap above height h on a unit sphere holds (1 - h) / 2 of the area.
    let relative: Vec<DVec3> = cloud.positions.iter().map(|p| (*p - center) / 2.0).collect();
    assert!((fraction(&relative, |p| p.y > 0.5) - 0.25).abs() < 0.005);
    assert!((fraction(&relative, |p| p.x > 0.0) - 0.5).abs() < 0.01);
}

#[test]
fn torus_points_are_on_the_torus_and_evenly_spread_by_area() {
    let (major, minor) = (1.0_f64, 0.5_f64);
    let cloud = torus_points(Vec3::ZERO, major as f32, minor as f32, 20_000);
    let normals = cloud.normals.as_ref().unwrap();
    for (p, n) in cloud.positions.iter().zip(normals) {
        let ring = DVec3::new(p.x, 0.0, p.z).normalize() * major;
        assert!(((*p - ring).length() - minor).abs() < 1e-5, "{p} is off the torus");
        assert!((*p - ring).normalize().as_vec3().dot(*n) > 0.9999, "outward");
    }
    // The outer half of the tube (farther from the axis than the ring) has more area:
    // (pi R + 2 r) / (2 pi R) of it. Uniform angles would put only half the points there.
    let outer = fraction(&cloud.positions, |p| (p.x * p.x + p.z * p.z).sqrt() > major);
    let expected = (std::f64::consts::PI * major + 2.0 * minor) / (std::f64::consts::TAU * major);
    assert!((outer - expected).abs() < 0.005, "outer fraction {outer}, expected {expected}");
}
