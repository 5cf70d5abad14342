// Twin of src/rough_plastic.rs: a white GGX dielectric coating over a Lambertian base, the
// base weighted by what the coating transmits both ways; one lobe drawn per sample.
#ifndef POINTRAY_ROUGH_PLASTIC_GLSL
#define POINTRAY_ROUGH_PLASTIC_GLSL

#include "bsdf_sample.glsl"
#include "fresnel.glsl"
#include "microfacet.glsl"
#include "sampling.glsl"

float rough_plastic_coat_probability(vec3 albedo, float ior, vec3 wo) {
    float coat = fresnel_dielectric(wo.z, ior);
    float base = (1.0 - coat) * (albedo.x + albedo.y + albedo.z) / 3.0;
    return clamp(coat / max(coat + base, 1e-6), 0.1, 0.9);
}

vec3 rough_plastic_eval(vec3 albedo, float alpha, float ior, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return vec3(0.0);
    }
    vec3 m = normalize(wo + wi);
    float coat = fresnel_dielectric(dot(wo, m), ior) * ggx_d(m, alpha) * smith_g2(wo, wi, alpha) / (4.0 * wo.z);
    float through = (1.0 - fresnel_dielectric(wi.z, ior)) * (1.0 - fresnel_dielectric(wo.z, ior));
    return vec3(coat) + albedo * (through * wi.z / SAMPLING_PI);
}

float rough_plastic_pdf(vec3 albedo, float alpha, float ior, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return 0.0;
    }
    vec3 m = normalize(wo + wi);
    float coat = ggx_visible_pdf(wo, m, alpha) / (4.0 * dot(wo, m));
    float p = rough_plastic_coat_probability(albedo, ior, wo);
    return p * coat + (1.0 - p) * cosine_hemisphere_pdf(wi.z);
}

BsdfSample rough_plastic_sample(vec3 albedo, float alpha, float ior, vec3 wo, vec3 u) {
    if (wo.z <= 0.0) {
        return bsdf_sample_none();
    }
    vec3 wi;
    if (u.z < rough_plastic_coat_probability(albedo, ior, wo)) {
        vec3 m = ggx_sample_visible(wo, alpha, u.xy);
        wi = 2.0 * dot(wo, m) * m - wo;
    } else {
        wi = cosine_hemisphere(u.xy);
    }
    float pdf = rough_plastic_pdf(albedo, alpha, ior, wo, wi);
    if (wi.z <= 0.0 || pdf <= 0.0) {
        return bsdf_sample_none();
    }
    return BsdfSample(wi, rough_plastic_eval(albedo, alpha, ior, wo, wi) / pdf, pdf, false);
}

#endif
