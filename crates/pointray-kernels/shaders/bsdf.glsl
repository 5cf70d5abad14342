// Twin of src/bsdf.rs: one record for every kind of BSDF and the dispatch to each.
// Opaque kinds are two-sided (the caller face-forwards the normal); glass keeps its normal.
#ifndef POINTRAY_BSDF_GLSL
#define POINTRAY_BSDF_GLSL

#include "dielectric.glsl"
#include "lambert.glsl"
#include "rough_conductor.glsl"
#include "rough_plastic.glsl"

const uint BSDF_DIFFUSE = 0u;
const uint BSDF_CONDUCTOR = 1u;
const uint BSDF_PLASTIC = 2u;
const uint BSDF_DIELECTRIC = 3u;

struct Bsdf {
    uint kind;
    vec3 color;
    float roughness;
    float ior;
};

bool bsdf_is_two_sided(Bsdf bsdf) {
    return bsdf.kind != BSDF_DIELECTRIC;
}

bool bsdf_samples_lights(Bsdf bsdf) {
    return bsdf.kind != BSDF_DIELECTRIC;
}

float bsdf_alpha(Bsdf bsdf) {
    return max(bsdf.roughness, MIN_ALPHA);
}

vec3 bsdf_eval(Bsdf bsdf, vec3 wo, vec3 wi) {
    switch (bsdf.kind) {
    case BSDF_DIFFUSE:
        return lambert_eval(bsdf.color, wo, wi);
    case BSDF_CONDUCTOR:
        return rough_conductor_eval(bsdf.color, bsdf_alpha(bsdf), wo, wi);
    case BSDF_PLASTIC:
        return rough_plastic_eval(bsdf.color, bsdf_alpha(bsdf), bsdf.ior, wo, wi);
    default:
        return vec3(0.0);
    }
}

float bsdf_pdf(Bsdf bsdf, vec3 wo, vec3 wi) {
    switch (bsdf.kind) {
    case BSDF_DIFFUSE:
        return lambert_pdf(wo, wi);
    case BSDF_CONDUCTOR:
        return rough_conductor_pdf(bsdf_alpha(bsdf), wo, wi);
    case BSDF_PLASTIC:
        return rough_plastic_pdf(bsdf.color, bsdf_alpha(bsdf), bsdf.ior, wo, wi);
    default:
        return 0.0;
    }
}

BsdfSample bsdf_sample(Bsdf bsdf, vec3 wo, vec3 u) {
    switch (bsdf.kind) {
    case BSDF_DIFFUSE:
        return lambert_sample(bsdf.color, wo, u.xy);
    case BSDF_CONDUCTOR:
        return rough_conductor_sample(bsdf.color, bsdf_alpha(bsdf), wo, u.xy);
    case BSDF_PLASTIC:
        return rough_plastic_sample(bsdf.color, bsdf_alpha(bsdf), bsdf.ior, wo, u);
    default:
        return dielectric_sample(bsdf.color, bsdf.roughness > 0.0 ? bsdf_alpha(bsdf) : 0.0, bsdf.ior, wo, u);
    }
}

#endif
