//! PCA normals on noise-free analytic surfaces against their exact normals.

use crate::normals_support;

use glam::Vec3;
use normals_support::{NORMAL_K, line_angle_degrees, oriented_normals};
use pointray_surface::neighbors::k_nearest;
use pointray_surface::normals::pca_normals;
use pointray_surface::orientation::orient_consistently;

const MAX_ERROR_DEGREES: f32 = 1.0;

/// `n` points evenly spread over a sphere (Fibonacci spiral).
fn fibonacci_sphere(n: usize, radius: f32, centre: Vec3) -> Vec<Vec3> {
    let golden_angle = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = golden_angle * i as f64;
            centre + radius * glam::DVec3::new(r * phi.cos(), r * phi.sin(), z).as_vec3()
        })
        .collect()
}

/// A deterministic value in [-0.5, 0.5), so grids are irregular but reproducible.
fn jitter(i: usize) -> f32 {
    let mut z = (i as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32 - 0.5
}

/// A jittered `n x n` grid over [-1, 1]² lifted to `z = f(x, y)`, with each point's
/// exact normal `(-f_x, -f_y, 1)`; points within `margin` of the border are flagged,
/// since their one-sided neighbourhoods tilt the PCA plane on curved surfaces.
fn height_field(n: usize, f: impl Fn(f32, f32) -> (f32, f32, f32)) -> (Vec<Vec3>, Vec<Vec3>, Vec<bool>) {
    let cell = 2.0 / n as f32;
    let margin = 1.0 - 4.0 * cell;
    let mut points = Vec::new();
    let mut normals = Vec::new();
    let mut interior = Vec::new();
    for i in 0..n * n {
        let x = -1.0 + cell * ((i % n) as f32 + 0.5 + 0.5 * jitter(2 * i));
        let y = -1.0 + cell * ((i / n) as f32 + 0.5 + 0.5 * jitter(2 * i + 1));
        let (z, fx, fy) = f(x, y);
        points.push(Vec3::new(x, y, z));
        normals.push(Vec3::new(-fx, -fy, 1.0).normalize());
        interior.push(x.abs() < margin && y.abs() < margin);
    }
    (points, normals, interior)
}

fn worst_error_degrees(found: &[Vec3], exact: &[Vec3], include: impl Fn(usize) -> bool) -> f32 {
    (0..found.len())
        .filter(|&i| include(i))
        .map(|i| line_angle_degrees(found[i], exact[i]))
        .fold(0.0, f32::max)
}

fn assert_height_field_normals(name: &str, f: impl Fn(f32, f32) -> (f32, f32, f32)) {
    let (points, exact, interior) = height_field(120, f);
    let neighbors = k_nearest(&points, NORMAL_K);
    let normals = pca_normals(&points, &neighbors, NORMAL_K);
    let worst = worst_error_degrees(&normals, &exact, |i| interior[i]);
    println!("{name}: worst interior normal error {worst:.4} deg");
    assert!(worst < MAX_ERROR_DEGREES, "{name}: normal error {worst} deg");
}

#[test]
fn plane_normals_are_exact() {
    assert_height_field_normals("plane", |x, y| (0.3 * x - 0.2 * y + 0.5, 0.3, -0.2));
}

#[test]
fn paraboloid_normals_match_gradient() {
    assert_height_field_normals("paraboloid", |x, y| (0.5 * (x * x + y * y), x, y));
}

#[test]
fn saddle_normals_match_gradient() {
    assert_height_field_normals("saddle", |x, y| (0.5 * (x * x - y * y), x, -y));
}

#[test]
fn sphere_normals_are_radial_and_consistently_oriented() {
    let centre = Vec3::new(1.0, -2.0, 0.5);
    let points = fibonacci_sphere(20_000, 3.0, centre);
    let radial: Vec<Vec3> = points.iter().map(|&p| (p - centre).normalize()).collect();
    let normals = oriented_normals(&points);

    let worst = worst_error_degrees(&normals, &radial, |_| true);
    println!("sphere: worst normal error {worst:.4} deg");
    assert!(worst < MAX_ERROR_DEGREES, "sphere normal error {worst} deg");
    let outward = normals.iter().zip(&radial).filter(|(n, r)| n.dot(**r) > 0.0).count();
    assert_eq!(outward, points.len(), "all outward (the highest point's normal points up)");
}

#[test]
fn each_component_is_oriented_outward() {
    let mut points = fibonacci_sphere(3000, 1.0, Vec3::ZERO);
    points.extend(fibonacci_sphere(2000, 0.5, Vec3::new(10.0, 0.0, -3.0)));
    let centre_of = |i: usize| if i < 3000 { Vec3::ZERO } else { Vec3::new(10.0, 0.0, -3.0) };
    let neighbors = k_nearest(&points, NORMAL_K);
    let mut normals = pca_normals(&points, &neighbors, NORMAL_K);
    // Scramble the signs so that orientation has work to do.
    for (i, n) in normals.iter_mut().enumerate() {
        if jitter(i) < 0.0 {
            *n = -*n;
        }
    }
    orient_consistently(&points, &mut normals, &neighbors);
    let inward: Vec<usize> =
        (0..points.len()).filter(|&i| normals[i].dot(points[i] - centre_of(i)) <= 0.0).collect();
    assert!(
        inward.is_empty(),
        "{} normals point inward, e.g. {:?}",
        inward.len(),
        &inward[..inward.len().min(5)]
    );
}

/// A torus around the x axis (tube radius `r` around a circle of radius `big_r` in the yz
/// plane), on a jittered `n x n` grid of its angles, with each point's outward normal.
fn standing_torus(n: usize, big_r: f32, r: f32) -> (Vec<Vec3>, Vec<Vec3>) {
    let tau = std::f32::consts::TAU;
    (0..n * n)
        .map(|i| {
            let u = tau * ((i % n) as f32 + 0.5 + 0.4 * jitter(2 * i)) / n as f32;
            let v = tau * ((i / n) as f32 + 0.5 + 0.4 * jitter(2 * i + 1)) / n as f32;
            let outward = Vec3::new(v.sin(), v.cos() * u.cos(), v.cos() * u.sin());
            (Vec3::new(0.0, big_r * u.cos(), big_r * u.sin()) + r * outward, outward)
        })
        .unzip()
}

#[test]
fn closed_torus_is_oriented_outward_across_many_blocks() {
    // 160,000 points make three orientation blocks. Standing on its rim, the torus is cut
    // by the Morton order into pieces whose own highest points face down, so only agreeing
    // with the pieces beside them orients those outward.
    let (points, outward) = standing_torus(400, 1.0, 0.3);
    let order = pointray_surface::morton::morton_order(&points);
    let sorted: Vec<Vec3> = order.iter().map(|&i| points[i as usize]).collect();
    let neighbors = k_nearest(&sorted, NORMAL_K);
    let mut normals = pca_normals(&sorted, &neighbors, NORMAL_K);
    for (i, n) in normals.iter_mut().enumerate() {
        if jitter(i + 77) < 0.0 {
            *n = -*n;
        }
    }
    orient_consistently(&sorted, &mut normals, &neighbors);
    let inward = (0..sorted.len()).filter(|&i| normals[i].dot(outward[order[i] as usize]) <= 0.0).count();
    assert_eq!(inward, 0, "{inward} of {} normals point into the torus", sorted.len());
}
