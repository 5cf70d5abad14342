//! A rough plastic: a GGX dielectric coating (white, index `ior`) over a Lambertian base of
//! colour `albedo`. Twin of `shaders/rough_plastic.glsl`.
//!
//! The base receives what the coating transmits on the way in and on the way out, `(1 -
//! F(θi)) (1 - F(θo))`, so the sum of the lobes never exceeds what arrives. One lobe is
//! drawn per sample, the coating with probability `rough_plastic_coat_probability`; the pdf
//! is the mixture's.

use core::f32::consts::FRAC_1_PI;

use glam::{Vec3, Vec3Swizzles};

use crate::bsdf_sample::BsdfSample;
use crate::fresnel::fresnel_dielectric;
use crate::microfacet::{ggx_d, ggx_sample_visible, ggx_visible_pdf, smith_g2};
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};

/// How often the coating is drawn: its share of what is reflected head on, kept within
/// [0.1, 0.9] so that neither lobe goes unsampled.
pub fn rough_plastic_coat_probability(albedo: Vec3, ior: f32, wo: Vec3) -> f32 {
    let coat = fresnel_dielectric(wo.z, ior);
    let base = (1.0 - coat) * (albedo.x + albedo.y + albedo.z) / 3.0;
    (coat / (coat + base).max(1e-6)).clamp(0.1, 0.9)
}

/// `f cos θi` of both lobes.
pub fn rough_plastic_eval(albedo: Vec3, alpha: f32, ior: f32, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    let m = (wo + wi).normalize();
    let coat = fresnel_dielectric(wo.dot(m), ior) * ggx_d(m, alpha) * smith_g2(wo, wi, alpha) / (4.0 * wo.z);
    let through = (1.0 - fresnel_dielectric(wi.z, ior)) * (1.0 - fresnel_dielectric(wo.z, ior));
    Vec3::splat(coat) + albedo * (through * FRAC_1_PI * wi.z)
}

pub fn rough_plastic_pdf(albedo: Vec3, alpha: f32, ior: f32, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let m = (wo + wi).normalize();
    let coat = ggx_visible_pdf(wo, m, alpha) / (4.0 * wo.dot(m));
    let p = rough_plastic_coat_probability(albedo, ior, wo);
    p * coat + (1.0 - p) * cosine_hemisphere_pdf(wi.z)
}

/// `u.z` picks the lobe, `u.xy` the direction within it.
pub fn rough_plastic_sample(albedo: Vec3, alpha: f32, ior: f32, wo: Vec3, u: Vec3) -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample::NONE;
    }
    let wi = if u.z < rough_plastic_coat_probability(albedo, ior, wo) {
        let m = ggx_sample_visible(wo, alpha, u.xy());
        2.0 * wo.dot(m) * m - wo
    } else {
        cosine_hemisphere(u.xy())
    };
    let pdf = rough_plastic_pdf(albedo, alpha, ior, wo, wi);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return BsdfSample::NONE;
    }
    BsdfSample {
        direction: wi,
        weight: rough_plastic_eval(albedo, alpha, ior, wo, wi) / pdf,
        pdf,
        delta: false,
    }
}
