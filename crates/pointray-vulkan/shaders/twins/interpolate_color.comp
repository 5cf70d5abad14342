#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define INPUTS_PER_CASE 2u
#define OUTPUTS_PER_CASE 1u
#include "twin_io.glsl"
#include "interpolate_color.glsl"

// Inputs: the position and the hit patch (uint bits); the addresses of the hot and cold
// buffers (uint bits). After the last case, one vec4 holds the colour neighbours' address.
// Output: the RGBA8 colour (uint bits).
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    vec4 query = case_input(i, 0u);
    uvec4 addresses = floatBitsToUint(case_input(i, 1u));
    uvec2 neighbor_address = floatBitsToUint(inputs[cases.case_count * INPUTS_PER_CASE].xy);
    uint color = interpolate_color(query.xyz, floatBitsToUint(query.w), HotPatches(addresses.xy),
                                   ColdPatches(addresses.zw), ColorNeighbors(neighbor_address));
    set_case_output(i, 0u, vec4(uintBitsToFloat(color), 0.0, 0.0, 0.0));
}
