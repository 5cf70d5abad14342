#version 460
// Miss shader 1: a shadow ray that reaches its light unblocked.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require

#include "payload.glsl"

layout(location = SHADOW_PAYLOAD_LOCATION) rayPayloadInEXT ShadowPayload shadow;

void main() {
    shadow.visible = 1u;
}
