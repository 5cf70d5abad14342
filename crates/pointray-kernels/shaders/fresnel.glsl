// Twin of src/fresnel.rs: Fresnel reflectance and refraction.
#ifndef POINTRAY_FRESNEL_GLSL
#define POINTRAY_FRESNEL_GLSL

// eta = index beyond / index on the incident side; 1 under total internal reflection.
float fresnel_dielectric(float cos_incident, float eta) {
    float cos_i = clamp(cos_incident, 0.0, 1.0);
    float sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) {
        return 1.0;
    }
    float cos_t = sqrt(1.0 - sin2_t);
    float s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (s * s + p * p);
}

vec3 fresnel_schlick(float cos_incident, vec3 f0) {
    float c = 1.0 - clamp(cos_incident, 0.0, 1.0);
    float c5 = c * c * c * c * c;
    return f0 + (vec3(1.0) - f0) * c5;
}

// `incident` points away from the surface on `normal`'s side; false under total internal
// reflection. Named apart from GLSL's built-in `refract`, which takes the other direction.
bool refract_direction(vec3 incident, vec3 normal, float eta, out vec3 refracted) {
    float cos_i = dot(incident, normal);
    float sin2_t = max(1.0 - cos_i * cos_i, 0.0) / (eta * eta);
    if (sin2_t >= 1.0) {
        refracted = vec3(0.0);
        return false;
    }
    float cos_t = sqrt(1.0 - sin2_t);
    refracted = -incident / eta + (cos_i / eta - cos_t) * normal;
    return true;
}

#endif
