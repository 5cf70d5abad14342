//! The GGX (Trowbridge-Reitz) microfacet distribution with Smith's height-correlated
//! shadowing, and Heitz's sampling of the normals a direction sees. Twin of
//! `shaders/microfacet.glsl`.
//!
//! Directions are local (the macro normal along +z) and lie above the surface; `alpha` is
//! GGX's width, as Mitsuba's `alpha`, at least `MIN_ALPHA`.

use core::f32::consts::PI;

use glam::{Vec2, Vec3};

/// Narrower lobes than this overflow f32 in `ggx_d` near the peak.
pub const MIN_ALPHA: f32 = 1e-3;

/// The density of micro-normals `m` per projected area, `D(m)`.
pub fn ggx_d(m: Vec3, alpha: f32) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = m.z * m.z * (a2 - 1.0) + 1.0;
    a2 / (PI * t * t)
}

/// Smith's Λ for GGX: the shadowing of direction `v`.
pub fn smith_lambda(v: Vec3, alpha: f32) -> f32 {
    let cos2 = v.z * v.z;
    if cos2 <= 0.0 {
        return f32::INFINITY;
    }
    let tan2 = (1.0 - cos2).max(0.0) / cos2;
    0.5 * ((1.0 + alpha * alpha * tan2).sqrt() - 1.0)
}

/// The fraction of the micro-surface that `v` sees, `G1`.
pub fn smith_g1(v: Vec3, alpha: f32) -> f32 {
    1.0 / (1.0 + smith_lambda(v, alpha))
}

/// The fraction seen from both `a` and `b`, height-correlated: `1 / (1 + Λ(a) + Λ(b))`.
pub fn smith_g2(a: Vec3, b: Vec3, alpha: f32) -> f32 {
    1.0 / (1.0 + smith_lambda(a, alpha) + smith_lambda(b, alpha))
}

/// A micro-normal drawn from the normals that `wo` sees, `D_wo(m) = G1(wo) max(wo·m, 0)
/// D(m) / wo.z` (Heitz, "Sampling the GGX Distribution of Visible Normals", 2018).
pub fn ggx_sample_visible(wo: Vec3, alpha: f32, u: Vec2) -> Vec3 {
    let stretched = Vec3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let length2 = stretched.x * stretched.x + stretched.y * stretched.y;
    let t1 = if length2 > 0.0 { Vec3::new(-stretched.y, stretched.x, 0.0) / length2.sqrt() } else { Vec3::X };
    let t2 = stretched.cross(t1);
    let radius = u.x.sqrt();
    let phi = 2.0 * PI * u.y;
    let p1 = radius * phi.cos();
    let s = 0.5 * (1.0 + stretched.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * radius * phi.sin();
    let lifted = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * stretched;
    Vec3::new(alpha * lifted.x, alpha * lifted.y, lifted.z.max(0.0)).normalize()
}

/// The density of `ggx_sample_visible` at `m`.
pub fn ggx_visible_pdf(wo: Vec3, m: Vec3, alpha: f32) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    smith_g1(wo, alpha) * wo.dot(m).max(0.0) * ggx_d(m, alpha) / wo.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::tests::halton;
    use crate::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};

    fn integrate_sphere(count: u32, f: impl Fn(Vec3) -> f32) -> f32 {
        let sum: f64 = (0..count).map(|i| f64::from(f(uniform_sphere(halton(i))))).sum();
        (sum / f64::from(count)) as f32 / UNIFORM_SPHERE_PDF
    }

    #[test]
    fn projected_micro_normals_cover_the_surface_once() {
        for alpha in [0.2, 0.5, 1.0] {
            let area = integrate_sphere(400_000, |m| ggx_d(m, alpha) * m.z.max(0.0));
            assert!((area - 1.0).abs() < 0.02, "alpha {alpha}: {area}");
        }
    }

    #[test]
    fn the_visible_normal_density_integrates_to_one() {
        let wo = Vec3::new(0.6, 0.2, 0.5).normalize();
        for alpha in [0.3, 0.8] {
            let total = integrate_sphere(400_000, |m| ggx_visible_pdf(wo, m, alpha));
            assert!((total - 1.0).abs() < 0.02, "alpha {alpha}: {total}");
        }
    }

    #[test]
    fn sampled_normals_follow_the_visible_density() {
        // E[m.z] under D_wo, by sampling and by integrating the density.
        let (wo, alpha) = (Vec3::new(0.5, -0.3, 0.6).normalize(), 0.5);
        let count = 100_000;
        let sampled: f32 =
            (0..count).map(|i| ggx_sample_visible(wo, alpha, halton(i)).z).sum::<f32>() / count as f32;
        let integrated = integrate_sphere(400_000, |m| m.z * ggx_visible_pdf(wo, m, alpha));
        assert!((sampled - integrated).abs() < 0.01, "{sampled} against {integrated}");
        for i in 0..1000 {
            let m = ggx_sample_visible(wo, alpha, halton(i));
            assert!(m.z >= 0.0 && wo.dot(m) >= -1e-5 && (m.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn shadowing_vanishes_head_on_and_grows_toward_grazing() {
        assert!((smith_g1(Vec3::Z, 0.5) - 1.0).abs() < 1e-6);
        let grazing = Vec3::new(0.99, 0.0, 0.141).normalize();
        assert!(smith_g1(grazing, 0.5) < smith_g1(Vec3::new(0.5, 0.0, 0.866), 0.5));
        assert!(smith_g2(grazing, grazing, 0.5) <= smith_g1(grazing, 0.5));
    }
}
