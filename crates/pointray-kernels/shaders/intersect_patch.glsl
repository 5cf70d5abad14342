// Twin of src/intersect_patch.rs: a ray against one quadratic patch (METHOD.md section 3).
// The box test uses the patch's own cube [p - d_u, p + d_u] from the hot record, which
// contains the stored AABB (see the Rust twin for why).
#ifndef POINTRAY_INTERSECT_PATCH_GLSL
#define POINTRAY_INTERSECT_PATCH_GLSL

#include "layout.glsl"
#include "patch_frame.glsl"
#include "quadratic_roots.glsl"
#include "ray.glsl"

const uint ACCEPTANCE_BOX = 0u;
const uint ACCEPTANCE_DISK = 1u;

// A, B, C of A t^2 + B t + C = 0 for the local ray o + t d against w = f(u, v).
vec3 patch_quadratic(Patch surface, vec3 o, vec3 d) {
    float c0 = surface.c0;
    float c1 = surface.c1;
    float c2 = surface.c2;
    float c3 = surface.c3;
    float c4 = surface.c4;
    float c5 = surface.c5;
    float a = -(c3 * d.x * d.x + c4 * d.x * d.y + c5 * d.y * d.y);
    float b = d.z - (c1 * d.x + c2 * d.y + 2.0 * c3 * o.x * d.x + c4 * (o.x * d.y + o.y * d.x)
                     + 2.0 * c5 * o.y * d.y);
    float f = c0 + c1 * o.x + c2 * o.y + c3 * o.x * o.x + c4 * o.x * o.y + c5 * o.y * o.y;
    return vec3(a, b, o.z - f);
}

bool patch_accepts(vec3 point, vec2 uv, Patch surface, uint acceptance) {
    bool in_box = all(lessThanEqual(abs(point - surface.origin), vec3(surface.radii.x)));
    if (acceptance == ACCEPTANCE_DISK) {
        return in_box && patch_supports(surface, uv);
    }
    return in_box;
}

// The smallest root in [t_min, t_max] that passes `acceptance`; false when none does.
bool intersect_patch(Ray ray, Patch surface, float t_min, float t_max, uint acceptance,
                     out float t_hit, out vec2 uv_hit) {
    t_hit = 0.0;
    uv_hit = vec2(0.0);
    vec3 o = patch_to_local(surface, ray.origin);
    vec3 d = patch_direction_to_local(surface, ray.direction);
    vec3 abc = patch_quadratic(surface, o, d);
    vec2 roots;
    uint count = quadratic_roots(abc.x, abc.y, abc.z, roots);
    for (uint i = 0u; i < count; ++i) {
        float t = roots[i];
        if (t < t_min || t > t_max) {
            continue;
        }
        vec2 uv = o.xy + t * d.xy;
        if (patch_accepts(ray_at(ray, t), uv, surface, acceptance)) {
            t_hit = t;
            uv_hit = uv;
            return true;
        }
    }
    return false;
}

#endif
