// Twin of src/ray.rs: a ray `origin + t * direction`.
#ifndef POINTRAY_RAY_GLSL
#define POINTRAY_RAY_GLSL

struct Ray {
    vec3 origin;
    vec3 direction;
};

vec3 ray_at(Ray ray, float t) {
    return ray.origin + t * ray.direction;
}

#endif
