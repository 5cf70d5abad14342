// Twin of src/patch_normal.rs: the gradient normal of a patch at local (u, v).
#ifndef POINTRAY_PATCH_NORMAL_GLSL
#define POINTRAY_PATCH_NORMAL_GLSL

#include "layout.glsl"
#include "patch_frame.glsl"

// Local (-f_u, -f_v, 1) in the patch's (object) space, unit length, on n_i's side.
vec3 patch_normal(Patch surface, vec2 uv) {
    float f_u = surface.c1 + 2.0 * surface.c3 * uv.x + surface.c4 * uv.y;
    float f_v = surface.c2 + surface.c4 * uv.x + 2.0 * surface.c5 * uv.y;
    return normalize(patch_direction_to_world(surface, vec3(-f_u, -f_v, 1.0)));
}

#endif
