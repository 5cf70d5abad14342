//! Point sets sampled on analytic surfaces, for scenes that need no data file. Samples are
//! deterministic and evenly spread (Fibonacci lattices), and carry the exact surface normals.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;

const GOLDEN_RATIO_FRACTION: f64 = 0.618_033_988_749_894_9;

/// `count` points evenly spread over a sphere (a spherical Fibonacci lattice).
pub fn sphere_points(center: Vec3, radius: f32, count: u32) -> PointCloud {
    let n = count as f64;
    let normals: Vec<DVec3> = (0..count)
        .map(|i| {
            let i = i as f64;
            let y = 1.0 - 2.0 * (i + 0.5) / n;
            let ring = (1.0 - y * y).max(0.0).sqrt();
            let azimuth = TAU * (i * GOLDEN_RATIO_FRACTION).fract();
            DVec3::new(ring * azimuth.cos(), y, ring * azimuth.sin())
        })
        .collect();
    let center = center.as_dvec3();
    let positions = normals.iter().map(|n| center + *n * radius as f64).collect();
    with_normals(positions, &normals)
}

/// `count` points evenly spread by area over a torus around the Y axis: the tube of radius
/// `minor_radius` circles the centre at distance `major_radius`.
pub fn torus_points(center: Vec3, major_radius: f32, minor_radius: f32, count: u32) -> PointCloud {
    let (major, minor) = (major_radius as f64, minor_radius as f64);
    let n = count as f64;
    let mut positions = Vec::with_capacity(count as usize);
    let mut normals = Vec::with_capacity(count as usize);
    for i in 0..count {
        let i = i as f64;
        let around_axis = TAU * (i + 0.5) / n;
        let around_tube = tube_angle_for_area_fraction((i * GOLDEN_RATIO_FRACTION).fract(), major, minor);
        let radial = DVec3::new(around_axis.cos(), 0.0, around_axis.sin());
        let normal = radial * around_tube.cos() + DVec3::Y * around_tube.sin();
        positions.push(center.as_dvec3() + radial * major + normal * minor);
        normals.push(normal);
    }
    with_normals(positions, &normals)
}

/// The outer side of a torus has more area than the inner side: the area up to tube angle `a`
/// is proportional to `major * a + minor * sin(a)`. This inverts that by Newton's method so that
/// uniform fractions give area-uniform angles.
fn tube_angle_for_area_fraction(fraction: f64, major: f64, minor: f64) -> f64 {
    let target = fraction * TAU * major;
    let mut angle = fraction * TAU - PI;
    // Measured from -pi so the function is monotone over the whole range.
    let area = |a: f64| major * (a + PI) + minor * a.sin();
    for _ in 0..8 {
        let slope = major + minor * angle.cos();
        angle -= (area(angle) - target) / slope.max(1e-9);
    }
    angle
}

fn with_normals(positions: Vec<DVec3>, normals: &[DVec3]) -> PointCloud {
    PointCloud {
        normals: Some(normals.iter().map(|n| n.as_vec3()).collect()),
        ..PointCloud::from_positions(positions)
    }
}
