#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#define INPUTS_PER_CASE 1u
#define OUTPUTS_PER_CASE 1u
#include "twin_io.glsl"
#include "patch_buffers.glsl"

// Input: a buffer's address (low, high), a record index and the record's size (uint bits).
// Output: the record's address (low, high; uint bits).
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    uvec4 query = floatBitsToUint(case_input(i, 0u));
    uvec2 address = record_address(query.xy, query.z, query.w);
    set_case_output(i, 0u, vec4(uintBitsToFloat(address), 0.0, 0.0));
}
