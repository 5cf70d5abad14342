#version 460
// Hit groups 0, 2 (compiled with PATCH_GROUPS) and 3 (with UNPACKED_RECORDS), closest hit:
// the patch's gradient normal and the point colours interpolated at the hit. Hit group 2's
// intersection shader names the patch of its box that it hit; the others' box is the patch.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "bindings.glsl"
#include "payload.glsl"
#include "patch_normal.glsl"
#include "interpolate_color.glsl"
#include "self_clearance.glsl"

layout(location = HIT_PAYLOAD_LOCATION) rayPayloadInEXT HitPayload payload;
#ifdef PATCH_GROUPS
hitAttributeEXT PatchHit hit;
#else
hitAttributeEXT vec2 hit_uv;
#endif

// The point colours interpolated at the hit, where the material uses them (white otherwise,
// which ray generation does not read). Blending reads the split hot and cold buffers, which
// every patch object whose material uses the point colours has, whatever the buffer layout.
uint hit_color(ObjectRecord object, uint patch_index) {
    if (object.specular_shininess_reflect_colors.w == 0.0) {
        return 0xffffffffu;
    }
    // In object space, where the patches are; t is the same there.
    vec3 position = gl_ObjectRayOriginEXT + gl_HitTEXT * gl_ObjectRayDirectionEXT;
    return interpolate_color(position, patch_index, object.hot, object.cold, object.color_neighbors);
}

void main() {
    ObjectRecord object = objects[gl_InstanceCustomIndexEXT];
#ifdef PATCH_GROUPS
    uint patch_index = hit.patch_index;
    vec2 uv = hit.uv;
#else
    uint patch_index = object.first_patch + gl_PrimitiveID + gl_GeometryIndexEXT;
    vec2 uv = hit_uv;
#endif
    Patch surface = load_patch(object, patch_index);
    vec3 object_normal = patch_normal(surface, uv);
    // Normals go to world by the inverse transpose: n * WorldToObject.
    payload.normal_or_background = normalize((object_normal * gl_WorldToObjectEXT).xyz);
    payload.t = gl_HitTEXT;
    payload.instance = gl_InstanceCustomIndexEXT;
    payload.primitive = patch_index;
    payload.color_rgba8 = hit_color(object, patch_index);
    // World lengths from the inverse transform's first column, as the CPU renderer does.
    float world_scale = 1.0 / length(gl_WorldToObjectEXT[0]);
    payload.clearance = self_clearance(surface.radii.x * world_scale);
}
