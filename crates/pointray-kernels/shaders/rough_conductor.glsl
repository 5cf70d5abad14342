// Twin of src/rough_conductor.rs: GGX reflection with Schlick's Fresnel from the colour.
#ifndef POINTRAY_ROUGH_CONDUCTOR_GLSL
#define POINTRAY_ROUGH_CONDUCTOR_GLSL

#include "bsdf_sample.glsl"
#include "fresnel.glsl"
#include "microfacet.glsl"

vec3 rough_conductor_eval(vec3 f0, float alpha, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3(0.0);
    }
    vec3 m = normalize(wo + wi);
    return fresnel_schlick(dot(wo, m), f0) * (ggx_d(m, alpha) * smith_g2(wo, wi, alpha) / (4.0 * wo.z));
}

float rough_conductor_pdf(float alpha, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return 0.0;
    }
    vec3 m = normalize(wo + wi);
    return ggx_visible_pdf(wo, m, alpha) / (4.0 * dot(wo, m));
}

BsdfSample rough_conductor_sample(vec3 f0, float alpha, vec3 wo, vec2 u) {
    if (wo.z <= 0.0) {
        return bsdf_sample_none();
    }
    vec3 m = ggx_sample_visible(wo, alpha, u);
    vec3 wi = 2.0 * dot(wo, m) * m - wo;
    if (wi.z <= 0.0) {
        return bsdf_sample_none();
    }
    vec3 weight = fresnel_schlick(dot(wo, m), f0) * (smith_g2(wo, wi, alpha) / smith_g1(wo, alpha));
    return BsdfSample(wi, weight, rough_conductor_pdf(alpha, wo, wi), false);
}

#endif
