#version 460
// Miss shader 0: primary and reflection rays see the background.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "bindings.glsl"
#include "payload.glsl"
#include "sky.glsl"

layout(location = HIT_PAYLOAD_LOCATION) rayPayloadInEXT HitPayload payload;

void main() {
    payload.normal_or_background = sky(gl_WorldRayDirectionEXT);
    payload.t = -1.0;
    payload.instance = MISS_ID;
    payload.primitive = MISS_ID;
}
