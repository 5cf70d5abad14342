// What a ray that leaves the scene sees, and how the path integrator draws directions toward
// it: the GLSL side of pointray-scene's `Background` (uniform over the sphere for a colour
// or a gradient, in proportion to the radiance for a map).
#ifndef POINTRAY_SKY_GLSL
#define POINTRAY_SKY_GLSL

#include "background.glsl"
#include "environment_map.glsl"

EnvironmentMap sky_map() {
    return EnvironmentMap(frame.sky_width, frame.sky_height, frame.sky_rotation);
}

vec3 sky(vec3 direction) {
    if (frame.sky_is_map != 0u) {
        return environment_radiance(sky_map(), direction);
    }
    return background(direction, frame.background_top.rgb, frame.background_bottom.rgb);
}

LightSample sky_sample(vec2 u) {
    if (frame.sky_is_map != 0u) {
        return environment_sample(sky_map(), u);
    }
    vec3 direction = uniform_sphere(u);
    return LightSample(direction, LIGHT_INFINITY, sky(direction), UNIFORM_SPHERE_PDF);
}

float sky_pdf(vec3 direction) {
    return frame.sky_is_map != 0u ? environment_pdf(sky_map(), direction) : UNIFORM_SPHERE_PDF;
}

#endif
