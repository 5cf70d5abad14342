// Twin of src/sampling.rs: directions drawn from uniform numbers, with their densities,
// and the frames they are drawn in (local directions have the normal along +z).
#ifndef POINTRAY_SAMPLING_GLSL
#define POINTRAY_SAMPLING_GLSL

const float SAMPLING_PI = 3.14159265358979;
const float UNIFORM_SPHERE_PDF = 0.25 / SAMPLING_PI;

// Duff et al. 2017: a right-handed frame around a unit normal without a branch on its axis.
void orthonormal_basis(vec3 normal, out vec3 tangent, out vec3 bitangent) {
    float sign_z = normal.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign_z + normal.z);
    float b = normal.x * normal.y * a;
    tangent = vec3(1.0 + sign_z * normal.x * normal.x * a, sign_z * b, -sign_z * normal.x);
    bitangent = vec3(b, sign_z + normal.y * normal.y * a, -normal.y);
}

vec3 to_local(vec3 world, vec3 normal) {
    vec3 tangent, bitangent;
    orthonormal_basis(normal, tangent, bitangent);
    return vec3(dot(world, tangent), dot(world, bitangent), dot(world, normal));
}

vec3 to_world(vec3 local, vec3 normal) {
    vec3 tangent, bitangent;
    orthonormal_basis(normal, tangent, bitangent);
    return local.x * tangent + local.y * bitangent + local.z * normal;
}

vec3 cosine_hemisphere(vec2 u) {
    float radius = sqrt(u.x);
    float phi = 2.0 * SAMPLING_PI * u.y;
    return vec3(radius * cos(phi), radius * sin(phi), sqrt(max(1.0 - u.x, 0.0)));
}

float cosine_hemisphere_pdf(float cos_theta) {
    return max(cos_theta, 0.0) / SAMPLING_PI;
}

vec3 uniform_sphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float radius = sqrt(max(1.0 - z * z, 0.0));
    float phi = 2.0 * SAMPLING_PI * u.y;
    return vec3(radius * cos(phi), radius * sin(phi), z);
}

vec3 uniform_cone(vec2 u, float cos_max) {
    float z = 1.0 - u.x * (1.0 - cos_max);
    float radius = sqrt(max(1.0 - z * z, 0.0));
    float phi = 2.0 * SAMPLING_PI * u.y;
    return vec3(radius * cos(phi), radius * sin(phi), z);
}

float uniform_cone_pdf(float cos_max) {
    return 1.0 / (2.0 * SAMPLING_PI * (1.0 - cos_max));
}

// Veach's power heuristic (beta = 2).
float power_heuristic(float chosen, float other) {
    float a = chosen * chosen;
    float b = other * other;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

#endif
