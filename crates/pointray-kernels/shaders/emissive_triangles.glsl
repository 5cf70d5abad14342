// Twin of src/emissive_triangles.rs: emissive mesh triangles as one light, a triangle drawn
// in proportion to its area and a point uniform on it, emitting from both sides.
//
// The includer defines EMISSIVE_RECORD(i) (a vec4: a triangle's three world-space corners,
// then its radiance, four records a triangle) and EMISSIVE_DISTRIBUTION(i) (a float: the
// cumulative areas, count + 1 of them).
#ifndef POINTRAY_EMISSIVE_TRIANGLES_GLSL
#define POINTRAY_EMISSIVE_TRIANGLES_GLSL

#include "light_source.glsl"

struct EmissiveTriangles {
    uint count;
    float total_area;
};

uint emissive_pick_triangle(EmissiveTriangles triangles, float u) {
    uint low = 0u;
    uint high = triangles.count;
    while (high - low > 1u) {
        uint middle = (low + high) / 2u;
        if (EMISSIVE_DISTRIBUTION(middle) <= u) {
            low = middle;
        } else {
            high = middle;
        }
    }
    return low;
}

float emissive_pdf(EmissiveTriangles triangles, float distance, float cos_theta) {
    float cosine = abs(cos_theta);
    if (cosine == 0.0 || triangles.total_area <= 0.0) {
        return 0.0;
    }
    return distance * distance / (cosine * triangles.total_area);
}

LightSample emissive_sample(EmissiveTriangles triangles, float pick, vec2 u, vec3 position) {
    uint triangle = emissive_pick_triangle(triangles, pick);
    vec3 a = EMISSIVE_RECORD(4u * triangle).xyz;
    vec3 b = EMISSIVE_RECORD(4u * triangle + 1u).xyz;
    vec3 c = EMISSIVE_RECORD(4u * triangle + 2u).xyz;
    float root = sqrt(u.x);
    vec3 point = a * (1.0 - root) + b * (u.y * root) + c * (root * (1.0 - u.y));
    vec3 offset = point - position;
    float distance2 = dot(offset, offset);
    if (distance2 <= 0.0) {
        return NO_LIGHT;
    }
    float distance = sqrt(distance2);
    vec3 direction = offset / distance;
    vec3 normal = normalize(cross(b - a, c - a));
    float pdf = emissive_pdf(triangles, distance, dot(normal, direction));
    if (pdf <= 0.0) {
        return NO_LIGHT;
    }
    return LightSample(direction, distance, EMISSIVE_RECORD(4u * triangle + 3u).xyz, pdf);
}

#endif
