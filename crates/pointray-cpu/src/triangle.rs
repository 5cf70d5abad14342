//! Ray against triangle: Möller–Trumbore, two-sided (no back-face culling), as the
//! Vulkan backend's opaque built-in triangle test.

use glam::Vec3;

use pointray_kernels::Ray;

/// The ray parameter where `ray` crosses triangle `(a, b, c)` within `[t_min, t_max]`.
pub fn intersect_triangle(ray: &Ray, [a, b, c]: [Vec3; 3], t_min: f32, t_max: f32) -> Option<f32> {
    let edge1 = b - a;
    let edge2 = c - a;
    let p = ray.direction.cross(edge2);
    let determinant = edge1.dot(p);
    if determinant == 0.0 {
        return None;
    }
    let inverse = 1.0 / determinant;
    let s = ray.origin - a;
    let u = s.dot(p) * inverse;
    // Written so that NaN (from a near-zero determinant) fails every test.
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(edge1);
    let v = ray.direction.dot(q) * inverse;
    if !(v >= 0.0 && u + v <= 1.0) {
        return None;
    }
    let t = edge2.dot(q) * inverse;
    (t_min..=t_max).contains(&t).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRIANGLE: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    #[test]
    fn hits_from_both_sides() {
        let front = Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z);
        let back = Ray::new(Vec3::new(0.2, 0.2, -2.0), Vec3::Z);
        assert_eq!(intersect_triangle(&front, TRIANGLE, 0.0, f32::INFINITY), Some(1.0));
        assert_eq!(intersect_triangle(&back, TRIANGLE, 0.0, f32::INFINITY), Some(2.0));
    }

    #[test]
    fn misses_outside_the_edges_parallel_or_out_of_range() {
        let outside = Ray::new(Vec3::new(0.6, 0.6, 1.0), Vec3::NEG_Z);
        let parallel = Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::X);
        let short = Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z);
        assert_eq!(intersect_triangle(&outside, TRIANGLE, 0.0, f32::INFINITY), None);
        assert_eq!(intersect_triangle(&parallel, TRIANGLE, 0.0, f32::INFINITY), None);
        assert_eq!(intersect_triangle(&short, TRIANGLE, 0.0, 0.5), None);
    }
}
