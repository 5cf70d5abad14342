// Twin of src/intersect_patch.rs: a ray against one quadratic patch (SPEC.md section 3).
// The box test uses the patch's own cube [p - d, p + d] from the hot record, which prep
// also stores as the patch's AABB (see the Rust twin for why).
#ifndef POINTRAY_INTERSECT_PATCH_GLSL
#define POINTRAY_INTERSECT_PATCH_GLSL

#include "layout.glsl"
#include "patch_frame.glsl"
#include "quadratic_roots.glsl"
#include "ray.glsl"

const uint ACCEPTANCE_BOX = 0u;
const uint ACCEPTANCE_DISK = 1u;

// A, B, C of A t^2 + B t + C = 0 for the local ray o + t d against w = f(u, v).
vec3 patch_quadratic(PatchHot hot, vec3 o, vec3 d) {
    float c0 = hot.tangent_c0.w;
    float c1 = hot.normal_c1.w;
    float c2 = hot.c2_c5.x;
    float c3 = hot.c2_c5.y;
    float c4 = hot.c2_c5.z;
    float c5 = hot.c2_c5.w;
    float a = -(c3 * d.x * d.x + c4 * d.x * d.y + c5 * d.y * d.y);
    float b = d.z - (c1 * d.x + c2 * d.y + 2.0 * c3 * o.x * d.x + c4 * (o.x * d.y + o.y * d.x)
                     + 2.0 * c5 * o.y * d.y);
    float f = c0 + c1 * o.x + c2 * o.y + c3 * o.x * o.x + c4 * o.x * o.y + c5 * o.y * o.y;
    return vec3(a, b, o.z - f);
}

bool patch_accepts(vec3 point, vec2 uv, PatchHot hot, uint acceptance) {
    float radius = patch_radius(hot);
    bool in_box = all(lessThanEqual(abs(point - patch_origin(hot)), vec3(radius)));
    if (acceptance == ACCEPTANCE_DISK) {
        return in_box && dot(uv, uv) <= radius * radius;
    }
    return in_box;
}

// The smallest root in [t_min, t_max] that passes `acceptance`; false when none does.
bool intersect_patch(Ray ray, PatchHot hot, float t_min, float t_max, uint acceptance,
                     out float t_hit, out vec2 uv_hit) {
    t_hit = 0.0;
    uv_hit = vec2(0.0);
    vec3 o = patch_to_local(hot, ray.origin);
    vec3 d = patch_direction_to_local(hot, ray.direction);
    vec3 abc = patch_quadratic(hot, o, d);
    vec2 roots;
    uint count = quadratic_roots(abc.x, abc.y, abc.z, roots);
    for (uint i = 0u; i < count; ++i) {
        float t = roots[i];
        if (t < t_min || t > t_max) {
            continue;
        }
        vec2 uv = o.xy + t * d.xy;
        if (patch_accepts(ray_at(ray, t), uv, hot, acceptance)) {
            t_hit = t;
            uv_hit = uv;
            return true;
        }
    }
    return false;
}

#endif
