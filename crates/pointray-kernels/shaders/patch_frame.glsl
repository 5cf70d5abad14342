// Twin of `Patch` and `PatchHot::decode` in src/layout.rs: a patch decoded from its hot
// record, and world <-> patch-local (u, v, w).
#ifndef POINTRAY_PATCH_FRAME_GLSL
#define POINTRAY_PATCH_FRAME_GLSL

#include "layout.glsl"
#include "tangent_frame.glsl"

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
    float aspect = unpackUnorm2x16(hot.aspect_c1).x;
    float c1 = unpackHalf2x16(hot.aspect_c1).y;
    float unit = hot.radius > 0.0 ? hot.radius : 1.0;
    vec2 c2_c3 = unpackHalf2x16(hot.c2_c3);
    vec2 c4_c5 = unpackHalf2x16(hot.c4_c5);
    return Patch(patch_origin(hot), unpack_frame(hot.frame), vec2(hot.radius, hot.radius * aspect), 0.0,
                 c1, c2_c3.x, c2_c3.y / unit, c4_c5.x / unit, c4_c5.y / unit);
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
    vec2 squared = surface.radii * surface.radii;
    return uv.x * uv.x * squared.y + uv.y * uv.y * squared.x <= squared.x * squared.y;
}

#endif
