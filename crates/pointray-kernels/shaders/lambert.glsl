// Twin of src/lambert.rs: the Lambertian BSDF albedo / pi (local directions above the surface).
#ifndef POINTRAY_LAMBERT_GLSL
#define POINTRAY_LAMBERT_GLSL

#include "bsdf_sample.glsl"
#include "sampling.glsl"

vec3 lambert_eval(vec3 albedo, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3(0.0);
    }
    return albedo * (wi.z / SAMPLING_PI);
}

float lambert_pdf(vec3 wo, vec3 wi) {
    return wo.z <= 0.0 ? 0.0 : cosine_hemisphere_pdf(wi.z);
}

BsdfSample lambert_sample(vec3 albedo, vec3 wo, vec2 u) {
    vec3 wi = cosine_hemisphere(u);
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return bsdf_sample_none();
    }
    return BsdfSample(wi, albedo, cosine_hemisphere_pdf(wi.z), false);
}

#endif
