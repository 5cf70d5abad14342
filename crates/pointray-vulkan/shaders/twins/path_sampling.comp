#version 460
#extension GL_GOOGLE_include_directive : require
#define INPUTS_PER_CASE 5u
#define OUTPUTS_PER_CASE 4u
#include "twin_io.glsl"
#include "random_sequence.glsl"
#include "bsdf.glsl"

// Inputs: seed, pixel x, y and sample (uint bits); the BSDF (kind as uint bits, colour);
// roughness, ior and u.x, u.y; wo and u.z; wi. Outputs: the sequence's first four numbers;
// the BSDF's value and pdf for (wo, wi); a sample's direction and pdf; its weight and
// whether it is a delta lobe.
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    uvec4 sequence_input = floatBitsToUint(case_input(i, 0u));
    RandomSequence sequence = random_sequence(sequence_input.x, sequence_input.yz, sequence_input.w);
    vec4 numbers;
    numbers.x = random_next(sequence);
    numbers.y = random_next(sequence);
    numbers.zw = random_next2(sequence);
    set_case_output(i, 0u, numbers);
    vec4 kind_color = case_input(i, 1u);
    vec4 roughness_ior_u = case_input(i, 2u);
    vec4 wo_u = case_input(i, 3u);
    vec3 wi = case_input(i, 4u).xyz;
    Bsdf bsdf = Bsdf(floatBitsToUint(kind_color.x), kind_color.yzw, roughness_ior_u.x, roughness_ior_u.y);
    set_case_output(i, 1u, vec4(bsdf_eval(bsdf, wo_u.xyz, wi), bsdf_pdf(bsdf, wo_u.xyz, wi)));
    BsdfSample drawn = bsdf_sample(bsdf, wo_u.xyz, vec3(roughness_ior_u.zw, wo_u.w));
    set_case_output(i, 2u, vec4(drawn.direction, drawn.pdf));
    set_case_output(i, 3u, vec4(drawn.weight, drawn.delta ? 1.0 : 0.0));
}
