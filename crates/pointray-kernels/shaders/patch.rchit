#version 460
// Hit group 0, closest hit: the patch's gradient normal and the point's colour.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "bindings.glsl"
#include "payload.glsl"
#include "patch_normal.glsl"
#include "self_clearance.glsl"

layout(location = HIT_PAYLOAD_LOCATION) rayPayloadInEXT HitPayload payload;
hitAttributeEXT vec2 hit_uv;

void main() {
    ObjectRecord object = objects[gl_InstanceCustomIndexEXT];
    uint patch_index = gl_PrimitiveID + gl_GeometryIndexEXT;
    PatchHot patch_record = load_hot(object, patch_index);
    vec3 object_normal = patch_normal(patch_record, hit_uv);
    // Normals go to world by the inverse transpose: n * WorldToObject.
    payload.normal_or_background = normalize((object_normal * gl_WorldToObjectEXT).xyz);
    payload.t = gl_HitTEXT;
    payload.instance = gl_InstanceCustomIndexEXT;
    payload.primitive = patch_index;
    payload.color_rgba8 = load_cold(object, patch_index).color_rgba8;
    // World lengths from the inverse transform's first column, as the CPU renderer does.
    float world_scale = 1.0 / length(gl_WorldToObjectEXT[0]);
    payload.clearance = self_clearance(patch_record.origin_radius.w * world_scale);
}
