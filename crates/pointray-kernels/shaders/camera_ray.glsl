// Twin of src/camera_ray.rs: primary rays as the rendering contract defines them.
#ifndef POINTRAY_CAMERA_RAY_GLSL
#define POINTRAY_CAMERA_RAY_GLSL

#include "ray.glsl"

// Where sample `s` falls inside its pixel: the centre for s = 0, then the R2 sequence.
vec2 sample_jitter(uint s) {
    if (s == 0u) {
        return vec2(0.5);
    }
    return fract(vec2(0.5) + float(s) * vec2(0.7548777, 0.5698403));
}

struct Camera {
    vec3 position;
    vec3 look_at;
    vec3 up;
    float vertical_fov_degrees;
};

// The primary ray through `pixel + jitter` of an image of `size` pixels (top row first).
Ray camera_ray(Camera camera, uvec2 size, uvec2 pixel, vec2 jitter) {
    vec3 forward = normalize(camera.look_at - camera.position);
    vec3 right = normalize(cross(forward, camera.up));
    vec3 true_up = cross(right, forward);
    float tan_half = tan(0.5 * radians(camera.vertical_fov_degrees));
    vec2 size_f = vec2(size);
    vec2 film = vec2(pixel) + jitter;
    vec2 ndc = vec2(2.0 * film.x / size_f.x - 1.0, 1.0 - 2.0 * film.y / size_f.y);
    float aspect = size_f.x / size_f.y;
    vec3 direction = normalize(forward + ndc.x * tan_half * aspect * right + ndc.y * tan_half * true_up);
    return Ray(camera.position, direction);
}

#endif
