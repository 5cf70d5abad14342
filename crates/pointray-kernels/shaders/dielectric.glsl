// Twin of src/dielectric.rs: smooth (alpha == 0) or rough glass, sampled only. Local +z is
// the outside; wo may lie on either side. Refraction scales radiance by 1 / eta^2.
#ifndef POINTRAY_DIELECTRIC_GLSL
#define POINTRAY_DIELECTRIC_GLSL

#include "bsdf_sample.glsl"
#include "fresnel.glsl"
#include "microfacet.glsl"

float dielectric_shadowing(float alpha, vec3 wo, vec3 wi) {
    return alpha > 0.0 ? smith_g2(wo, wi, alpha) / smith_g1(wo, alpha) : 1.0;
}

BsdfSample dielectric_sample(vec3 tint, float alpha, float ior, vec3 wo, vec3 u) {
    float side = wo.z >= 0.0 ? 1.0 : -1.0;
    float eta = side > 0.0 ? ior : 1.0 / ior;
    vec3 outside_wo = vec3(wo.x, wo.y, wo.z * side);
    vec3 m = alpha > 0.0 ? ggx_sample_visible(outside_wo, alpha, u.xy) : vec3(0.0, 0.0, 1.0);
    float cos_o = dot(outside_wo, m);
    if (outside_wo.z <= 0.0 || cos_o <= 0.0) {
        return bsdf_sample_none();
    }
    float reflectance = fresnel_dielectric(cos_o, eta);
    bool reflected = u.z < reflectance;
    vec3 wi;
    vec3 weight;
    if (reflected) {
        wi = 2.0 * cos_o * m - outside_wo;
        weight = vec3(dielectric_shadowing(alpha, outside_wo, wi));
    } else {
        if (!refract_direction(outside_wo, m, eta, wi)) {
            return bsdf_sample_none();
        }
        weight = tint * (dielectric_shadowing(alpha, outside_wo, wi) / (eta * eta));
    }
    if ((wi.z > 0.0) != reflected || wi.z == 0.0) {
        return bsdf_sample_none();
    }
    return BsdfSample(vec3(wi.xy, wi.z * side), weight, 0.0, true);
}

#endif
