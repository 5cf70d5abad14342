// Twin of src/layout.rs: per-patch records as the shaders read them (std430).
#ifndef POINTRAY_LAYOUT_GLSL
#define POINTRAY_LAYOUT_GLSL

struct PatchHot {
    vec4 origin_radius;  // p_i, d_i
    vec4 tangent_c0;     // t1, c0
    vec4 normal_c1;      // n_i, c1
    vec4 c2_c5;          // c2, c3, c4, c5
};

struct PatchCold {
    uint color_rgba8;    // linear RGBA8, r in the low byte
    float intensity;
    float color_reach;   // how far the point's colour reaches in the blend (interpolate_color)
};

#endif
