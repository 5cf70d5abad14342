// Ray payloads. Hit shaders only report what they hit; ray generation shades (the
// iterative path of the rendering contract), so payloads stay small.
#ifndef POINTRAY_PAYLOAD_GLSL
#define POINTRAY_PAYLOAD_GLSL

const uint MISS_ID = 0xffffffffu;

struct HitPayload {
    vec3 normal_or_background; // geometric world normal (not face-forwarded), or the background on a miss
    float t;
    uint instance;             // the ObjectRecord's index (gl_InstanceCustomIndexEXT); MISS_ID on a miss
    uint primitive;            // the patch's index in its whole set, or the triangle's
    uint color_rgba8;          // the point's colour (white for meshes)
    float clearance;           // secondary rays leaving the hit start at this t (self_clearance)
};

struct ShadowPayload {
    uint visible;
};

const int HIT_PAYLOAD_LOCATION = 0;
const int SHADOW_PAYLOAD_LOCATION = 1;

#endif
