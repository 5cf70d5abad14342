// Twin of src/microfacet.rs: GGX with Smith's height-correlated shadowing, and the sampling
// of visible normals (Heitz 2018). Local directions, the macro normal along +z.
#ifndef POINTRAY_MICROFACET_GLSL
#define POINTRAY_MICROFACET_GLSL

const float MICROFACET_PI = 3.14159265358979;
const float MIN_ALPHA = 1e-3;

float ggx_d(vec3 m, float alpha) {
    if (m.z <= 0.0) {
        return 0.0;
    }
    float a2 = alpha * alpha;
    float t = m.z * m.z * (a2 - 1.0) + 1.0;
    return a2 / (MICROFACET_PI * t * t);
}

float smith_lambda(vec3 v, float alpha) {
    float cos2 = v.z * v.z;
    if (cos2 <= 0.0) {
        return 1.0 / 0.0;
    }
    float tan2 = max(1.0 - cos2, 0.0) / cos2;
    return 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

float smith_g1(vec3 v, float alpha) {
    return 1.0 / (1.0 + smith_lambda(v, alpha));
}

float smith_g2(vec3 a, vec3 b, float alpha) {
    return 1.0 / (1.0 + smith_lambda(a, alpha) + smith_lambda(b, alpha));
}

vec3 ggx_sample_visible(vec3 wo, float alpha, vec2 u) {
    vec3 stretched = normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
    float length2 = stretched.x * stretched.x + stretched.y * stretched.y;
    vec3 t1 = length2 > 0.0 ? vec3(-stretched.y, stretched.x, 0.0) / sqrt(length2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(stretched, t1);
    float radius = sqrt(u.x);
    float phi = 2.0 * MICROFACET_PI * u.y;
    float p1 = radius * cos(phi);
    float s = 0.5 * (1.0 + stretched.z);
    float p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * radius * sin(phi);
    vec3 lifted = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * stretched;
    return normalize(vec3(alpha * lifted.x, alpha * lifted.y, max(lifted.z, 0.0)));
}

float ggx_visible_pdf(vec3 wo, vec3 m, float alpha) {
    if (wo.z <= 0.0) {
        return 0.0;
    }
    return smith_g1(wo, alpha) * max(dot(wo, m), 0.0) * ggx_d(m, alpha) / wo.z;
}

#endif
