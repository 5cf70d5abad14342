// Twin of src/layout.rs: per-patch records as the shaders read them (std430).
#ifndef POINTRAY_LAYOUT_GLSL
#define POINTRAY_LAYOUT_GLSL

// 36 bytes; decode_patch (patch_frame.glsl) unpacks it.
#define PATCH_HOT_BYTES 36u
struct PatchHot {
    float origin_x;
    float origin_y;
    float origin_z;
    float radius;        // d_u, the larger support radius
    uint normal;         // octahedral normal, two snorm16
    uint angle_aspect;   // angle of t1 / pi (unorm16, low), d_v / d_u (unorm16, high)
    uint c0_c1;          // c0 / d_u, c1 (half floats)
    uint c2_c3;          // c2, c3 d_u
    uint c4_c5;          // c4 d_u, c5 d_u
};

vec3 patch_origin(PatchHot hot) {
    return vec3(hot.origin_x, hot.origin_y, hot.origin_z);
}

#define PATCH_COLD_BYTES 12u
struct PatchCold {
    uint color_rgba8;    // linear RGBA8, r in the low byte
    float intensity;
    float color_reach;   // how far the point's colour reaches in the blend (interpolate_color)
};

#endif
