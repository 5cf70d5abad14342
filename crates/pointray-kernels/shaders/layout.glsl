// Twin of src/layout.rs: per-patch records as the shaders read them (std430).
#ifndef POINTRAY_LAYOUT_GLSL
#define POINTRAY_LAYOUT_GLSL

// 32 bytes; decode_patch (patch_frame.glsl) unpacks it. c0 is folded into the origin.
#define PATCH_HOT_BYTES 32u
struct PatchHot {
    float origin_x;      // p_i + c0 n_i
    float origin_y;
    float origin_z;
    float radius;        // d_u, the larger support radius
    uint frame;          // octahedral normal (two snorm11, low), angle of t1 / pi (unorm10, high)
    uint aspect_c1;      // d_v / d_u (unorm16, low), c1 (half float, high)
    uint c2_c3;          // c2, c3 d_u (half floats)
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
