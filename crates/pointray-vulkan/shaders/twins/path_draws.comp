#version 460
// The path integrator's draws: the random sequence (which must agree bit for bit), a BSDF
// sample and a quad light sample made from its numbers.
#extension GL_GOOGLE_include_directive : require
#define INPUTS_PER_CASE 2u
#define OUTPUTS_PER_CASE 3u
#include "twin_io.glsl"
#include "bsdf.glsl"
#include "light_source.glsl"
#include "random_sequence.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    uvec4 key = floatBitsToUint(case_input(i, 0u)); // seed, pixel x, pixel y, sample
    vec4 wo_roughness = case_input(i, 1u);
    RandomSequence random = random_sequence(key.x, key.yz, key.w);
    vec4 u = vec4(random_next(random), random_next(random), random_next(random), random_next(random));
    set_case_output(i, 0u, u);
    Bsdf plastic = Bsdf(BSDF_PLASTIC, vec3(0.8, 0.5, 0.3), wo_roughness.w, 1.5);
    BsdfSample drawn = bsdf_sample(plastic, wo_roughness.xyz, u.xyz);
    set_case_output(i, 1u, vec4(drawn.direction, drawn.pdf));
    LightSource quad = LightSource(LIGHT_QUAD, vec3(-0.5, 2.0, -0.5), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0), 0.0,
                                   vec3(1.0));
    LightSample arriving = light_sample(quad, vec3(0.0), u.zw);
    set_case_output(i, 2u, vec4(arriving.direction, arriving.pdf));
}
