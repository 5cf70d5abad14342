// Twin of the frame methods of `PatchHot` in src/layout.rs: world <-> patch-local (u, v, w).
#ifndef POINTRAY_PATCH_FRAME_GLSL
#define POINTRAY_PATCH_FRAME_GLSL

#include "layout.glsl"

vec3 patch_origin(PatchHot hot) {
    return hot.origin_radius.xyz;
}

float patch_radius(PatchHot hot) {
    return hot.origin_radius.w;
}

vec3 patch_tangent_u(PatchHot hot) {
    return hot.tangent_c0.xyz;
}

vec3 patch_normal_axis(PatchHot hot) {
    return hot.normal_c1.xyz;
}

// t2 = n x t1: the frame is right-handed and t2 is not stored.
vec3 patch_tangent_v(PatchHot hot) {
    return cross(patch_normal_axis(hot), patch_tangent_u(hot));
}

vec3 patch_direction_to_local(PatchHot hot, vec3 world) {
    return vec3(dot(world, patch_tangent_u(hot)), dot(world, patch_tangent_v(hot)),
                dot(world, patch_normal_axis(hot)));
}

vec3 patch_to_local(PatchHot hot, vec3 world) {
    return patch_direction_to_local(hot, world - patch_origin(hot));
}

vec3 patch_direction_to_world(PatchHot hot, vec3 local) {
    return local.x * patch_tangent_u(hot) + local.y * patch_tangent_v(hot) + local.z * patch_normal_axis(hot);
}

#endif
