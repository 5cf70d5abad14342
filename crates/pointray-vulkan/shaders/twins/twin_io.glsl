// The frame of every twin probe: case i reads INPUTS_PER_CASE vec4s from `inputs` and
// writes OUTPUTS_PER_CASE vec4s to `outputs` (uints travel as float bits). Each probe
// defines both counts before including this file.
#ifndef POINTRAY_TWIN_IO_GLSL
#define POINTRAY_TWIN_IO_GLSL

layout(local_size_x = 64) in;
layout(set = 0, binding = 0, std430) readonly buffer Inputs { vec4 inputs[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Outputs { vec4 outputs[]; };
layout(push_constant) uniform Cases { uint case_count; } cases;

vec4 case_input(uint i, uint j) {
    return inputs[i * INPUTS_PER_CASE + j];
}

void set_case_output(uint i, uint j, vec4 value) {
    outputs[i * OUTPUTS_PER_CASE + j] = value;
}

#endif
