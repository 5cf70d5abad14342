#version 460
// Hit group 1, closest hit: a mesh triangle's face normal.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "bindings.glsl"
#include "payload.glsl"

layout(location = HIT_PAYLOAD_LOCATION) rayPayloadInEXT HitPayload payload;

void main() {
    ObjectRecord object = objects[gl_InstanceCustomIndexEXT];
    uint first = 3u * uint(gl_PrimitiveID);
    vec3 a = mesh_vertex(object, first);
    vec3 b = mesh_vertex(object, first + 1u);
    vec3 c = mesh_vertex(object, first + 2u);
    vec3 object_normal = cross(b - a, c - a);
    payload.normal_or_background = normalize((object_normal * gl_WorldToObjectEXT).xyz);
    payload.t = gl_HitTEXT;
    payload.instance = gl_InstanceCustomIndexEXT;
    payload.primitive = uint(gl_PrimitiveID);
    payload.color_rgba8 = 0xffffffffu;
    payload.clearance = 0.0;
}
