#version 460
#extension GL_GOOGLE_include_directive : require
#define INPUTS_PER_CASE 5u
#define OUTPUTS_PER_CASE 2u
#include "twin_io.glsl"
#include "intersect_patch.glsl"
#include "patch_normal.glsl"

// Inputs: the PatchHot words (2 vec4s: origin and radius, then the four packed words), the
// acceptance, the ray's origin and t_max, its direction. Outputs: hit, t, uv; the
// patch normal at uv.
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    vec4 a = case_input(i, 0u);
    uvec4 b = floatBitsToUint(case_input(i, 1u));
    uvec4 c = floatBitsToUint(case_input(i, 2u));
    vec4 origin = case_input(i, 3u);
    vec4 direction = case_input(i, 4u);
    Patch surface = decode_patch(PatchHot(a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w));
    float t = 0.0;
    vec2 uv = vec2(0.0);
    bool hit = intersect_patch(Ray(origin.xyz, direction.xyz), surface, 0.0, origin.w, c.x, t, uv);
    set_case_output(i, 0u, vec4(hit ? 1.0 : 0.0, t, uv));
    set_case_output(i, 1u, vec4(patch_normal(surface, uv), 0.0));
}
