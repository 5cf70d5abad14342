//! The Lambertian diffuse BSDF, `albedo / π`. Twin of `shaders/lambert.glsl`.
//!
//! Local directions; both must lie above the surface (the caller turns the normal toward
//! the arriving ray).

use core::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use crate::bsdf_sample::BsdfSample;
use crate::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};

/// `f cos θi`.
pub fn lambert_eval(albedo: Vec3, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    albedo * (FRAC_1_PI * wi.z)
}

pub fn lambert_pdf(wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 { 0.0 } else { cosine_hemisphere_pdf(wi.z) }
}

/// Cosine-weighted: the weight is the albedo.
pub fn lambert_sample(albedo: Vec3, wo: Vec3, u: Vec2) -> BsdfSample {
    let wi = cosine_hemisphere(u);
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return BsdfSample::NONE;
    }
    BsdfSample { direction: wi, weight: albedo, pdf: cosine_hemisphere_pdf(wi.z), delta: false }
}
