#version 460
#extension GL_GOOGLE_include_directive : require
#define INPUTS_PER_CASE 1u
#define OUTPUTS_PER_CASE 1u
#include "twin_io.glsl"
#include "quadratic_roots.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    vec4 abc = case_input(i, 0u);
    vec2 roots = vec2(0.0);
    uint count = quadratic_roots(abc.x, abc.y, abc.z, roots);
    set_case_output(i, 0u, vec4(roots, float(count), 0.0));
}
