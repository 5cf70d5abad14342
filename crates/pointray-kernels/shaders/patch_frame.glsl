// Twin of `Patch` and `PatchHot::decode` in src/layout.rs: a patch decoded from its hot
// record, and world <-> patch-local (u, v, w).
#ifndef POINTRAY_PATCH_FRAME_GLSL
#define POINTRAY_PATCH_FRAME_GLSL

#include "layout.glsl"
#include "tangent_frame.glsl"

const float PI = 3.14159265358979;

struct Patch {
    vec3 origin;
    TangentFrame frame;
    vec2 radii;          // (d_u, d_v)
    float c0;
    float c1;
    float c2;
    float c3;
    float c4;
    float c5;
};

Patch decode_patch(PatchHot hot) {
    vec2 angle_aspect = unpackUnorm2x16(hot.angle_aspect);
    TangentFrame frame = tangent_frame_from_normal_and_angle(unpack_normal(hot.normal), angle_aspect.x * PI);
    float unit = hot.radius > 0.0 ? hot.radius : 1.0;
    vec2 c0_c1 = unpackHalf2x16(hot.c0_c1);
    vec2 c2_c3 = unpackHalf2x16(hot.c2_c3);
    vec2 c4_c5 = unpackHalf2x16(hot.c4_c5);
    return Patch(patch_origin(hot), frame,
                 vec2(hot.radius, hot.radius * angle_aspect.y), c0_c1.x * unit, c0_c1.y, c2_c3.x,
                 c2_c3.y / unit, c4_c5.x / unit, c4_c5.y / unit);
}

vec3 patch_direction_to_local(Patch surface, vec3 world) {
    return vec3(dot(world, surface.frame.t1), dot(world, surface.frame.t2), dot(world, surface.frame.n));
}

vec3 patch_to_local(Patch surface, vec3 world) {
    return patch_direction_to_local(surface, world - surface.origin);
}

vec3 patch_direction_to_world(Patch surface, vec3 local) {
    return local.x * surface.frame.t1 + local.y * surface.frame.t2 + local.z * surface.frame.n;
}

bool patch_supports(Patch surface, vec2 uv) {
    vec2 scaled = uv / surface.radii;
    return dot(scaled, scaled) <= 1.0;
}

#endif
