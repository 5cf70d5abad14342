// Twin of src/light_source.rs: point, directional, sphere and quad lights for next-event
// estimation. A point light's radiance is its intensity, a directional light's its
// irradiance, an area light's its emitted radiance; a quad emits toward edge_u x edge_v and
// is black (and opaque) behind.
#ifndef POINTRAY_LIGHT_SOURCE_GLSL
#define POINTRAY_LIGHT_SOURCE_GLSL

#include "sampling.glsl"

const uint LIGHT_POINT = 0u;
const uint LIGHT_DIRECTIONAL = 1u;
const uint LIGHT_SPHERE = 2u;
const uint LIGHT_QUAD = 3u;
const float LIGHT_INFINITY = 1.0 / 0.0;

struct LightSource {
    uint kind;
    vec3 position;
    vec3 edge_u;
    vec3 edge_v;
    float radius;
    vec3 radiance;
};

struct LightSample {
    vec3 direction;
    float distance;
    vec3 radiance;
    float pdf;
};

const LightSample NO_LIGHT = LightSample(vec3(0.0, 0.0, 1.0), 0.0, vec3(0.0), 0.0);

bool light_is_delta(LightSource light) {
    return light.kind == LIGHT_POINT || light.kind == LIGHT_DIRECTIONAL;
}

float light_hit(LightSource light, vec3 origin, vec3 direction) {
    if (light.kind == LIGHT_SPHERE) {
        vec3 offset = origin - light.position;
        float b = dot(offset, direction);
        float c = dot(offset, offset) - light.radius * light.radius;
        float discriminant = b * b - c;
        if (c <= 0.0 || discriminant < 0.0) {
            return LIGHT_INFINITY;
        }
        float t = -b - sqrt(discriminant);
        return t > 0.0 ? t : LIGHT_INFINITY;
    }
    if (light.kind == LIGHT_QUAD) {
        vec3 normal = cross(light.edge_u, light.edge_v);
        float facing = dot(direction, normal);
        if (facing == 0.0) {
            return LIGHT_INFINITY;
        }
        float t = dot(light.position - origin, normal) / facing;
        vec3 local = origin + t * direction - light.position;
        float a = dot(local, light.edge_u) / dot(light.edge_u, light.edge_u);
        float b = dot(local, light.edge_v) / dot(light.edge_v, light.edge_v);
        bool inside = t > 0.0 && a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0;
        return inside ? t : LIGHT_INFINITY;
    }
    return LIGHT_INFINITY;
}

// What a ray along `direction` receives from an area light it met: none from behind a quad.
vec3 light_emitted(LightSource light, vec3 direction) {
    bool behind = light.kind == LIGHT_QUAD && dot(direction, cross(light.edge_u, light.edge_v)) >= 0.0;
    return light_is_delta(light) || behind ? vec3(0.0) : light.radiance;
}

float light_pdf(LightSource light, vec3 position, vec3 direction, float distance) {
    if (light.kind == LIGHT_SPHERE) {
        vec3 offset = light.position - position;
        float distance2 = dot(offset, offset);
        float radius2 = light.radius * light.radius;
        if (distance2 <= radius2) {
            return 0.0;
        }
        return uniform_cone_pdf(sqrt(max(1.0 - radius2 / distance2, 0.0)));
    }
    if (light.kind == LIGHT_QUAD) {
        vec3 normal = cross(light.edge_u, light.edge_v);
        float area = length(normal);
        float cos_light = -dot(direction, normal) / area;
        return cos_light <= 0.0 ? 0.0 : distance * distance / (cos_light * area);
    }
    return 0.0;
}

LightSample sphere_light_sample(LightSource light, vec3 position, vec2 u) {
    vec3 offset = light.position - position;
    float distance2 = dot(offset, offset);
    float radius2 = light.radius * light.radius;
    if (distance2 <= radius2) {
        return NO_LIGHT;
    }
    float cos_max = sqrt(max(1.0 - radius2 / distance2, 0.0));
    vec3 direction = to_world(uniform_cone(u, cos_max), offset / sqrt(distance2));
    float distance = light_hit(light, position, direction);
    if (isinf(distance)) {
        return NO_LIGHT;
    }
    return LightSample(direction, distance, light.radiance, uniform_cone_pdf(cos_max));
}

LightSample quad_light_sample(LightSource light, vec3 position, vec2 u) {
    vec3 offset = light.position + u.x * light.edge_u + u.y * light.edge_v - position;
    float distance2 = dot(offset, offset);
    if (distance2 <= 0.0) {
        return NO_LIGHT;
    }
    float distance = sqrt(distance2);
    vec3 direction = offset / distance;
    float pdf = light_pdf(light, position, direction, distance);
    if (pdf <= 0.0) {
        return NO_LIGHT;
    }
    return LightSample(direction, distance, light.radiance, pdf);
}

LightSample light_sample(LightSource light, vec3 position, vec2 u) {
    if (light.kind == LIGHT_POINT) {
        vec3 offset = light.position - position;
        float distance2 = dot(offset, offset);
        if (distance2 <= 0.0) {
            return NO_LIGHT;
        }
        float distance = sqrt(distance2);
        return LightSample(offset / distance, distance, light.radiance / distance2, 0.0);
    }
    if (light.kind == LIGHT_DIRECTIONAL) {
        return LightSample(-normalize(light.edge_u), LIGHT_INFINITY, light.radiance, 0.0);
    }
    if (light.kind == LIGHT_SPHERE) {
        return sphere_light_sample(light, position, u);
    }
    return quad_light_sample(light, position, u);
}

#endif
