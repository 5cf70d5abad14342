//! Glass: a smooth (`alpha == 0`) or rough (GGX) boundary of index `ior` that reflects and
//! refracts by Fresnel. Twin of `shaders/dielectric.glsl`.
//!
//! Unlike the opaque BSDFs this one is one-sided: local +z is the outside (the side the
//! surface's normal faces, outward on a closed mesh or a point set prepped with consistent
//! normals), and `wo` may lie on either side. Its lobes are sampled only (the smooth one is
//! a delta; the rough one's evaluation is left out for the same reason: a path through
//! glass reaches the lights by the directions it draws), so `delta` is set on both.
//! Refraction scales radiance by `1 / eta²`.

use glam::{Vec3, Vec3Swizzles};

use crate::bsdf_sample::BsdfSample;
use crate::fresnel::{fresnel_dielectric, refract_direction};
use crate::microfacet::{ggx_sample_visible, smith_g1, smith_g2};

/// `u.xy` draws the micro-normal (rough glass), `u.z` picks reflection or refraction.
/// `tint` colours the transmission.
pub fn dielectric_sample(tint: Vec3, alpha: f32, ior: f32, wo: Vec3, u: Vec3) -> BsdfSample {
    // Work on wo's side: mirror the frame when wo is inside, and back at the end.
    let side = if wo.z >= 0.0 { 1.0 } else { -1.0 };
    let eta = if side > 0.0 { ior } else { 1.0 / ior };
    let outside_wo = Vec3::new(wo.x, wo.y, wo.z * side);
    let m = if alpha > 0.0 { ggx_sample_visible(outside_wo, alpha, u.xy()) } else { Vec3::Z };
    let cos_o = outside_wo.dot(m);
    if outside_wo.z <= 0.0 || cos_o <= 0.0 {
        return BsdfSample::NONE;
    }
    let shadowing = |wi: Vec3| {
        if alpha > 0.0 { smith_g2(outside_wo, wi, alpha) / smith_g1(outside_wo, alpha) } else { 1.0 }
    };
    let reflected = u.z < fresnel_dielectric(cos_o, eta);
    let (wi, weight) = if reflected {
        let wi = 2.0 * cos_o * m - outside_wo;
        (wi, Vec3::splat(shadowing(wi)))
    } else {
        match refract_direction(outside_wo, m, eta) {
            Some(wi) => (wi, tint * (shadowing(wi) / (eta * eta))),
            None => return BsdfSample::NONE,
        }
    };
    if (wi.z > 0.0) != reflected || wi.z == 0.0 {
        return BsdfSample::NONE;
    }
    BsdfSample { direction: Vec3::new(wi.x, wi.y, wi.z * side), weight, pdf: 0.0, delta: true }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::tests::halton;

    fn sample(alpha: f32, wo: Vec3, i: u32) -> BsdfSample {
        let u = halton(i);
        let pick = ((i as f32 + 0.5) * 0.618_034).fract();
        dielectric_sample(Vec3::ONE, alpha, 1.5, wo, Vec3::new(u.x, u.y, pick))
    }

    #[test]
    fn head_on_glass_reflects_four_percent_and_transmits_the_rest() {
        let count = 100_000;
        let reflected = (0..count).filter(|&i| sample(0.0, Vec3::Z, i).direction.z > 0.0).count();
        let fraction = reflected as f32 / count as f32;
        assert!((fraction - 0.04).abs() < 0.002, "{fraction}");
        let through =
            (0..count).map(|i| sample(0.0, Vec3::Z, i)).find(|s| s.direction.z < 0.0).expect("a refraction");
        assert!((through.direction - Vec3::NEG_Z).length() < 1e-6);
        assert!((through.weight.x - 1.0 / 2.25).abs() < 1e-6, "radiance scales by 1/eta²");
    }

    #[test]
    fn the_flux_of_smooth_and_rough_glass_is_conserved_both_ways() {
        // Each sample carries weight × eta² (undoing the radiance scaling) of flux; reflected
        // and transmitted flux add to one for smooth glass and at most one for rough glass.
        for wo in [Vec3::new(0.3, 0.0, 0.954).normalize(), Vec3::new(0.6, 0.2, -0.5).normalize()] {
            for alpha in [0.0, 0.3] {
                let count = 50_000;
                let flux: f32 = (0..count)
                    .map(|i| {
                        let s = sample(alpha, wo, i);
                        let crossed = (s.direction.z > 0.0) != (wo.z > 0.0);
                        let eta = if wo.z > 0.0 { 1.5f32 } else { 1.0 / 1.5 };
                        s.weight.x * if crossed { eta * eta } else { 1.0 }
                    })
                    .sum::<f32>()
                    / count as f32;
                assert!(flux <= 1.0 + 1e-3, "wo {wo} alpha {alpha}: {flux}");
                if alpha == 0.0 {
                    assert!((flux - 1.0).abs() < 1e-3, "wo {wo}: {flux}");
                } else {
                    assert!(flux > 0.75, "rough glass loses only what its shadowing hides: {flux}");
                }
            }
        }
    }

    #[test]
    fn light_inside_beyond_the_critical_angle_is_reflected_whole() {
        let wo = Vec3::new(0.8, 0.0, -0.6); // 53° from the normal, inside
        for i in 0..100 {
            let s = sample(0.0, wo, i);
            assert!(s.direction.z < 0.0 && (s.weight.x - 1.0).abs() < 1e-6);
        }
    }
}
