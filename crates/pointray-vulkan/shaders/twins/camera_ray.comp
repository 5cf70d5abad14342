#version 460
#extension GL_GOOGLE_include_directive : require
#define INPUTS_PER_CASE 4u
#define OUTPUTS_PER_CASE 2u
#include "twin_io.glsl"
#include "camera_ray.glsl"

// Inputs: position and vertical fov, look_at, up, then width, height, pixel x, y (uint
// bits). Outputs: the ray's origin and direction for sample i % 16's jitter.
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    vec4 position_fov = case_input(i, 0u);
    Camera camera = Camera(position_fov.xyz, case_input(i, 1u).xyz, case_input(i, 2u).xyz, position_fov.w);
    uvec4 size_pixel = floatBitsToUint(case_input(i, 3u));
    Ray ray = camera_ray(camera, size_pixel.xy, size_pixel.zw, sample_jitter(i % 16u));
    set_case_output(i, 0u, vec4(ray.origin, 0.0));
    set_case_output(i, 1u, vec4(ray.direction, 0.0));
}
