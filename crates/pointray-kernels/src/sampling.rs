//! Directions drawn from uniform numbers, with their densities (per steradian), and the
//! frames they are drawn in. Twin of `shaders/sampling.glsl`.
//!
//! Local directions have the surface normal (or the cone's axis) along +z.

use core::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

/// Two unit tangents completing `normal` (unit length) to a right-handed frame, without
/// a branch on which axis the normal is near (Duff et al., "Building an Orthonormal Basis,
/// Revisited", 2017).
pub fn orthonormal_basis(normal: Vec3) -> (Vec3, Vec3) {
    let sign = if normal.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + normal.z);
    let b = normal.x * normal.y * a;
    let tangent = Vec3::new(1.0 + sign * normal.x * normal.x * a, sign * b, -sign * normal.x);
    let bitangent = Vec3::new(b, sign + normal.y * normal.y * a, -normal.y);
    (tangent, bitangent)
}

/// `world` in the frame whose z axis is `normal`.
pub fn to_local(world: Vec3, normal: Vec3) -> Vec3 {
    let (tangent, bitangent) = orthonormal_basis(normal);
    Vec3::new(world.dot(tangent), world.dot(bitangent), world.dot(normal))
}

/// `local`, given in the frame whose z axis is `normal`, in world coordinates.
pub fn to_world(local: Vec3, normal: Vec3) -> Vec3 {
    let (tangent, bitangent) = orthonormal_basis(normal);
    local.x * tangent + local.y * bitangent + local.z * normal
}

/// A direction on the +z hemisphere with density `cos θ / π` (Malley's method).
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let radius = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(radius * phi.cos(), radius * phi.sin(), (1.0 - u.x).max(0.0).sqrt())
}

/// The density of `cosine_hemisphere` at a direction of local `cos_theta`.
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// A direction uniform on the unit sphere.
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let radius = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(radius * phi.cos(), radius * phi.sin(), z)
}

/// The density of `uniform_sphere`.
pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

/// A direction uniform in the cone about +z of half-angle `acos(cos_max)`.
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let z = 1.0 - u.x * (1.0 - cos_max);
    let radius = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(radius * phi.cos(), radius * phi.sin(), z)
}

/// The density of `uniform_cone`.
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

/// Veach's power heuristic (β = 2): the weight of a sample drawn with density `chosen` when
/// the other strategy would have drawn it with density `other`.
pub fn power_heuristic(chosen: f32, other: f32) -> f32 {
    let (a, b) = (chosen * chosen, other * other);
    if a + b > 0.0 { a / (a + b) } else { 0.0 }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A reproducible stream of uniform pairs for Monte Carlo checks (a 2D Halton sequence:
    /// its error falls as 1/n, so tight bounds stay quick).
    pub(crate) fn halton(index: u32) -> Vec2 {
        let radical = |mut i: u32, base: u32| {
            let (mut value, mut scale) = (0.0f64, 1.0f64 / f64::from(base));
            while i > 0 {
                value += f64::from(i % base) * scale;
                i /= base;
                scale /= f64::from(base);
            }
            value as f32
        };
        Vec2::new(radical(index + 1, 2), radical(index + 1, 3))
    }

    #[test]
    fn the_basis_is_orthonormal_for_every_normal_direction() {
        for i in 0..2000 {
            let normal = uniform_sphere(halton(i));
            let (t, b) = orthonormal_basis(normal);
            for (x, y) in [(t, b), (t, normal), (b, normal)] {
                assert!(x.dot(y).abs() < 1e-5, "{normal}");
            }
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
            assert!((t.cross(b) - normal).length() < 1e-5, "right-handed at {normal}");
            let v = Vec3::new(0.3, -0.5, 0.8);
            assert!((to_world(to_local(v, normal), normal) - v).length() < 1e-5);
        }
    }

    /// The Monte Carlo estimate of ∫ f over the sphere by uniform directions.
    fn integrate_sphere(count: u32, f: impl Fn(Vec3) -> f32) -> f32 {
        let sum: f64 = (0..count).map(|i| f64::from(f(uniform_sphere(halton(i))))).sum();
        (sum / f64::from(count)) as f32 / UNIFORM_SPHERE_PDF
    }

    #[test]
    fn each_density_integrates_to_one_over_the_sphere() {
        let count = 200_000;
        let cosine = integrate_sphere(count, |d| cosine_hemisphere_pdf(d.z));
        let cos_max = 0.8;
        let cone = integrate_sphere(count, |d| if d.z >= cos_max { uniform_cone_pdf(cos_max) } else { 0.0 });
        assert!((cosine - 1.0).abs() < 0.01, "cosine hemisphere: {cosine}");
        assert!((cone - 1.0).abs() < 0.01, "cone: {cone}");
    }

    #[test]
    fn samples_follow_their_densities() {
        // The mean of cos θ is 2/3 under the cosine density, 0 on the sphere, and
        // (1 + cos_max) / 2 in a uniform cone.
        let count = 100_000;
        let mean = |f: &dyn Fn(Vec2) -> Vec3| (0..count).map(|i| f(halton(i)).z).sum::<f32>() / count as f32;
        assert!((mean(&cosine_hemisphere) - 2.0 / 3.0).abs() < 1e-3);
        assert!(mean(&uniform_sphere).abs() < 1e-3);
        assert!((mean(&|u| uniform_cone(u, 0.6)) - 0.8).abs() < 1e-3);
        for i in 0..1000 {
            let u = halton(i);
            assert!((cosine_hemisphere(u).length() - 1.0).abs() < 1e-5);
            assert!(uniform_cone(u, 0.6).z >= 0.6 - 1e-6);
        }
    }

    #[test]
    fn the_power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (0.3, 2.0), (5.0, 0.0)] {
            assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
