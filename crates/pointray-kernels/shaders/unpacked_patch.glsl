// Twin of src/unpacked_patch.rs: a hot record unpacked at upload, read as it is.
#ifndef POINTRAY_UNPACKED_PATCH_GLSL
#define POINTRAY_UNPACKED_PATCH_GLSL

#include "patch_frame.glsl"

#define PATCH_UNPACKED_BYTES 64u
struct PatchUnpacked {
    vec4 origin_radius;        // origin, d_u
    vec4 tangent_minor_radius; // t1, d_v
    vec4 normal_c1;            // n, c1
    vec4 c2_c5;
};

Patch unpacked_patch(PatchUnpacked record) {
    vec3 t1 = record.tangent_minor_radius.xyz;
    vec3 n = record.normal_c1.xyz;
    return Patch(record.origin_radius.xyz, TangentFrame(t1, cross(n, t1), n),
                 vec2(record.origin_radius.w, record.tangent_minor_radius.w), 0.0, record.normal_c1.w,
                 record.c2_c5.x, record.c2_c5.y, record.c2_c5.z, record.c2_c5.w);
}

#endif
