#version 460
#extension GL_GOOGLE_include_directive : require
#define INPUTS_PER_CASE 6u
#define OUTPUTS_PER_CASE 3u
#include "twin_io.glsl"
#include "phong.glsl"
#include "face_forward.glsl"
#include "srgb_encode.glsl"
#include "self_clearance.glsl"
#include "tangent_frame.glsl"

// Inputs: normal, to_viewer, to_light, radiance (each .xyz), the surface (diffuse.xyz,
// specular), then shininess, a radius, a packed normal word and a tangent angle.
// Outputs: Phong and the face-forwarded normal; the sRGB RGBA8 word of the radiance and
// the self-clearance; the unpacked normal and its basis's first tangent.
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= cases.case_count) return;
    vec3 normal = case_input(i, 0u).xyz;
    vec3 to_viewer = case_input(i, 1u).xyz;
    vec3 to_light = case_input(i, 2u).xyz;
    vec3 radiance = case_input(i, 3u).xyz;
    vec4 surface = case_input(i, 4u);
    vec4 more = case_input(i, 5u);
    vec3 lit = phong(normal, to_viewer, to_light, radiance, PhongSurface(surface.xyz, surface.w, more.x));
    set_case_output(i, 0u, vec4(lit, 0.0));
    set_case_output(i, 1u, vec4(face_forward(normal, to_viewer), uintBitsToFloat(srgb_encode_rgba8(radiance))));
    vec3 unpacked = unpack_normal(floatBitsToUint(more.z));
    TangentFrame frame = tangent_frame_from_normal_and_angle(unpacked, more.w);
    set_case_output(i, 2u, vec4(frame.t1, self_clearance(more.y)));
}
