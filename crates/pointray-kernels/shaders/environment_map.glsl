// Twin of src/environment_map.rs: an equirectangular map's radiance in a direction, and
// directions drawn in proportion to its luminance, with their densities (Mitsuba 3's
// conventions: +y up, the top row straight up, u running with atan2(x, -z)).
//
// The includer says where the map's data lies by defining ENVIRONMENT_TEXEL(i) (a vec4,
// row-major from the top row) and ENVIRONMENT_DISTRIBUTION(i) (a float: height + 1
// cumulative row weights, then width + 1 for each row).
#ifndef POINTRAY_ENVIRONMENT_MAP_GLSL
#define POINTRAY_ENVIRONMENT_MAP_GLSL

#include "light_source.glsl"

struct EnvironmentMap {
    uint width;
    uint height;
    float rotation; // turns about +y: the map's u is the direction's u plus this
};

vec2 environment_uv(EnvironmentMap map, vec3 direction) {
    float u = atan(direction.x, -direction.z) * (0.5 / SAMPLING_PI) + map.rotation;
    float v = acos(clamp(direction.y, -1.0, 1.0)) * (1.0 / SAMPLING_PI);
    return vec2(u - floor(u), v);
}

vec3 environment_direction(EnvironmentMap map, vec2 uv) {
    float phi = 2.0 * SAMPLING_PI * (uv.x - map.rotation);
    float theta = SAMPLING_PI * uv.y;
    return vec3(sin(phi) * sin(theta), cos(theta), -cos(phi) * sin(theta));
}

uvec2 environment_texel(EnvironmentMap map, vec2 uv) {
    return uvec2(min(uint(uv.x * float(map.width)), map.width - 1u), min(uint(uv.y * float(map.height)), map.height - 1u));
}

vec3 environment_texel_radiance(EnvironmentMap map, uvec2 texel) {
    return ENVIRONMENT_TEXEL(texel.y * map.width + texel.x).rgb;
}

vec3 environment_radiance(EnvironmentMap map, vec3 direction) {
    return environment_texel_radiance(map, environment_texel(map, environment_uv(map, direction)));
}

// Texel (x, y)'s share of the draws over its area.
float environment_texel_density(EnvironmentMap map, uvec2 texel) {
    uint row = map.height + 1u + texel.y * (map.width + 1u);
    float row_share = ENVIRONMENT_DISTRIBUTION(texel.y + 1u) - ENVIRONMENT_DISTRIBUTION(texel.y);
    float texel_share = ENVIRONMENT_DISTRIBUTION(row + texel.x + 1u) - ENVIRONMENT_DISTRIBUTION(row + texel.x);
    return row_share * texel_share * float(map.width * map.height);
}

float environment_pdf(EnvironmentMap map, vec3 direction) {
    float sin_theta = sqrt(max(1.0 - direction.y * direction.y, 0.0));
    if (sin_theta == 0.0) {
        return 0.0;
    }
    uvec2 texel = environment_texel(map, environment_uv(map, direction));
    return environment_texel_density(map, texel) / (2.0 * SAMPLING_PI * SAMPLING_PI * sin_theta);
}

// The last of the `count` intervals starting at `offset` whose start lies at or below `u`;
// where in it `u` falls goes to `fraction`.
uint environment_sample_cumulative(uint offset, uint count, float u, out float fraction) {
    uint low = 0u;
    uint high = count;
    while (high - low > 1u) {
        uint middle = (low + high) / 2u;
        if (ENVIRONMENT_DISTRIBUTION(offset + middle) <= u) {
            low = middle;
        } else {
            high = middle;
        }
    }
    float start = ENVIRONMENT_DISTRIBUTION(offset + low);
    float width = ENVIRONMENT_DISTRIBUTION(offset + low + 1u) - start;
    fraction = width > 0.0 ? clamp((u - start) / width, 0.0, 1.0) : 0.0;
    return low;
}

LightSample environment_sample(EnvironmentMap map, vec2 u) {
    float fraction_y;
    float fraction_x;
    uint y = environment_sample_cumulative(0u, map.height, u.y, fraction_y);
    uint x = environment_sample_cumulative(map.height + 1u + y * (map.width + 1u), map.width, u.x, fraction_x);
    vec2 uv = vec2((float(x) + fraction_x) / float(map.width), (float(y) + fraction_y) / float(map.height));
    vec3 direction = environment_direction(map, uv);
    float sin_theta = sin(SAMPLING_PI * uv.y);
    float pdf = sin_theta > 0.0
        ? environment_texel_density(map, uvec2(x, y)) / (2.0 * SAMPLING_PI * SAMPLING_PI * sin_theta)
        : 0.0;
    return LightSample(direction, LIGHT_INFINITY, environment_texel_radiance(map, uvec2(x, y)), pdf);
}

#endif
