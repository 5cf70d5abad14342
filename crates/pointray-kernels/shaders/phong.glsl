// Twin of src/phong.rs: one light's Phong contribution (the rendering contract).
// The colour at a hit is ambient * C + the sum over visible lights of phong(...).
#ifndef POINTRAY_PHONG_GLSL
#define POINTRAY_PHONG_GLSL

struct PhongSurface {
    vec3 base_color;
    float specular;
    float shininess;
};

// radiance * (max(N.L, 0) C + specular max(R.V, 0)^shininess), R = reflect(-L, N);
// no specular when N.L <= 0. All vectors unit length; radiance = colour * intensity.
vec3 phong(vec3 normal, vec3 to_viewer, vec3 to_light, vec3 radiance, PhongSurface surface) {
    float n_dot_l = dot(normal, to_light);
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    vec3 reflected = 2.0 * n_dot_l * normal - to_light;
    float r_dot_v = dot(reflected, to_viewer);
    // pow(0, y) is undefined in GLSL: only raise a positive base.
    float highlight = r_dot_v > 0.0 ? pow(r_dot_v, surface.shininess) : 0.0;
    return radiance * (n_dot_l * surface.base_color + vec3(surface.specular * highlight));
}

#endif
