//! A rough metal: GGX microfacets reflecting with Schlick's Fresnel from the metal's colour
//! head on. Twin of `shaders/rough_conductor.glsl`.
//!
//! Local directions above the surface; `alpha` as in `microfacet`.

use glam::{Vec2, Vec3};

use crate::bsdf_sample::BsdfSample;
use crate::fresnel::fresnel_schlick;
use crate::microfacet::{ggx_d, ggx_sample_visible, ggx_visible_pdf, smith_g1, smith_g2};

/// `f cos θi = F D G2 / (4 cos θo)`.
pub fn rough_conductor_eval(f0: Vec3, alpha: f32, wo: Vec3, wi: Vec3) -> Vec3 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return Vec3::ZERO;
    }
    let m = (wo + wi).normalize();
    fresnel_schlick(wo.dot(m), f0) * (ggx_d(m, alpha) * smith_g2(wo, wi, alpha) / (4.0 * wo.z))
}

/// Visible normals, reflected: `D_wo(m) / (4 wo·m)`.
pub fn rough_conductor_pdf(alpha: f32, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let m = (wo + wi).normalize();
    ggx_visible_pdf(wo, m, alpha) / (4.0 * wo.dot(m))
}

pub fn rough_conductor_sample(f0: Vec3, alpha: f32, wo: Vec3, u: Vec2) -> BsdfSample {
    if wo.z <= 0.0 {
        return BsdfSample::NONE;
    }
    let m = ggx_sample_visible(wo, alpha, u);
    let wi = 2.0 * wo.dot(m) * m - wo;
    if wi.z <= 0.0 {
        return BsdfSample::NONE;
    }
    let weight = fresnel_schlick(wo.dot(m), f0) * (smith_g2(wo, wi, alpha) / smith_g1(wo, alpha));
    BsdfSample { direction: wi, weight, pdf: rough_conductor_pdf(alpha, wo, wi), delta: false }
}
