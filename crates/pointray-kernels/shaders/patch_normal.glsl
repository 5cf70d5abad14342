// Twin of src/patch_normal.rs: the gradient normal of a hot at local (u, v).
#ifndef POINTRAY_PATCH_NORMAL_GLSL
#define POINTRAY_PATCH_NORMAL_GLSL

#include "layout.glsl"
#include "patch_frame.glsl"

// Local (-f_u, -f_v, 1) in the hot's (object) space, unit length, on n_i's side.
vec3 patch_normal(PatchHot hot, vec2 uv) {
    float c1 = hot.normal_c1.w;
    float c2 = hot.c2_c5.x;
    float c3 = hot.c2_c5.y;
    float c4 = hot.c2_c5.z;
    float c5 = hot.c2_c5.w;
    float f_u = c1 + 2.0 * c3 * uv.x + c4 * uv.y;
    float f_v = c2 + c4 * uv.x + 2.0 * c5 * uv.y;
    return normalize(patch_direction_to_world(hot, vec3(-f_u, -f_v, 1.0)));
}

#endif
