// The path integrator of path.rgen (primary.rgen compiled with PATH_TRACING): the same
// algorithm as pointray-cpu's path_tracer.rs and direct_light.rs, over the kernels' GLSL
// twins, drawing the same random numbers in the same order, so that both backends follow the
// same paths. Included by primary.rgen after its payloads and trace_segment.
#ifndef POINTRAY_PATH_TRACER_GLSL
#define POINTRAY_PATH_TRACER_GLSL

#include "bsdf.glsl"
#include "emissive_triangles.glsl"
#include "light_source.glsl"
#include "random_sequence.glsl"
#include "self_clearance.glsl"
#include "sky.glsl"

// The numbers each bounce draws: light choice (1), light position (2), BSDF (3), roulette (1).
const uint BOUNCE_DIMENSIONS = 7u;
const uint ROULETTE_AFTER = 3u;
const float MAX_SURVIVAL = 0.95;

LightSource light_source_of(uint index) {
    LightRecord record = lights[index];
    return LightSource(uint(record.radiance.a), record.origin_radius.xyz, record.edge_u.xyz, record.edge_v.xyz,
                       record.origin_radius.w, record.radiance.rgb);
}

bool is_black(vec3 v) {
    return all(equal(v, vec3(0.0)));
}

// The lights, the sky unless it is black, and the emissive triangles if any.
uint emitter_count() {
    return frame.light_count + frame.sky_lit + (frame.emissive_count > 0u ? 1u : 0u);
}

EmissiveTriangles emissive_triangles() {
    return EmissiveTriangles(frame.emissive_count, frame.emissive_total_area);
}

// The emission a path's ray meets, `t` along it, on a surface of normal `normal`: weighed
// against light sampling where it is an emissive triangle (clearance 0) that light sampling
// could have drawn.
vec3 surface_emission(vec3 emission, float clearance, vec3 normal, Ray ray, float t, float arrival_pdf,
                      bool arrival_unweighted) {
    bool is_triangle = clearance == 0.0;
    if (is_black(emission) || !is_triangle || arrival_unweighted || frame.emissive_count == 0u) {
        return emission;
    }
    float choice = 1.0 / float(emitter_count());
    float light_density = emissive_pdf(emissive_triangles(), t, dot(normal, ray.direction));
    return emission * power_heuristic(arrival_pdf, choice * light_density);
}

// Off the surface by path_ray_offset on the side `direction` leaves to.
vec3 leaving(vec3 position, vec3 normal, float clearance, vec3 direction) {
    float side = dot(direction, normal) >= 0.0 ? 1.0 : -1.0;
    return position + normal * (side * path_ray_offset(clearance, frame.ray_epsilon));
}

// Whether a surface or another area light lies between the point and the light sample.
bool blocked(vec3 position, vec3 normal, float clearance, LightSample arriving, uint light) {
    vec3 origin = leaving(position, normal, clearance, arriving.direction);
    // Aimed from the ray's origin, off the surface, at the point sampled on the light, and
    // stopping short of it (an emissive triangle's own surface is in the TLAS).
    vec3 direction = arriving.direction;
    float distance = INFINITE_T;
    if (!isinf(arriving.distance)) {
        vec3 to_light = position + arriving.direction * arriving.distance - origin;
        float length_to_light = length(to_light);
        direction = to_light / length_to_light;
        distance = length_to_light * (1.0 - 1e-4);
    }
    for (uint i = 0u; i < frame.light_count; ++i) {
        if (i != light && light_hit(light_source_of(i), origin, direction) < distance) {
            return true;
        }
    }
    shadow.visible = 0u;
    uint flags = gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsSkipClosestHitShaderEXT;
    COUNT_RAY();
    traceRayEXT(scene_tlas, flags, 0xffu, HIT_SHADER_OFFSET, HIT_SHADER_STRIDE, SHADOW_MISS, origin, 0.0,
                direction, distance, SHADOW_PAYLOAD_LOCATION);
    return shadow.visible == 0u;
}

// Next-event estimation: one light (the sky, the emissive triangles) drawn, weighed against the BSDF.
vec3 direct_light(vec3 position, vec3 normal, float clearance, Bsdf bsdf, vec3 shading, vec3 wo,
                  inout RandomSequence random) {
    float pick = random_next(random);
    vec2 u = random_next2(random);
    uint count = emitter_count();
    if (count == 0u || !bsdf_samples_lights(bsdf)) {
        return vec3(0.0);
    }
    uint index = min(uint(pick * float(count)), count - 1u);
    LightSample arriving;
    bool delta = false;
    if (index < frame.light_count) {
        LightSource source = light_source_of(index);
        arriving = light_sample(source, position, u);
        delta = light_is_delta(source);
    } else if (index == frame.light_count && frame.sky_lit != 0u) {
        arriving = sky_sample(u);
    } else {
        // What is left of `pick` within the triangles' share picks the triangle.
        float within = clamp(pick * float(count) - float(index), 0.0, 1.0);
        arriving = emissive_sample(emissive_triangles(), within, u, position);
    }
    if (is_black(arriving.radiance) || (!delta && arriving.pdf <= 0.0)) {
        return vec3(0.0);
    }
    vec3 wi = to_local(arriving.direction, shading);
    vec3 reflected = bsdf_eval(bsdf, wo, wi);
    if (is_black(reflected) || blocked(position, normal, clearance, arriving, index)) {
        return vec3(0.0);
    }
    float choice = 1.0 / float(count);
    if (delta) {
        return reflected * arriving.radiance / choice;
    }
    float weight = power_heuristic(choice * arriving.pdf, bsdf_pdf(bsdf, wo, wi));
    return reflected * arriving.radiance * (weight / (choice * arriving.pdf));
}

// The nearest area light on the ray before `surface_t`, or -1.
int light_on(Ray ray, float surface_t, out float light_t) {
    int nearest = -1;
    light_t = surface_t;
    for (uint i = 0u; i < frame.light_count; ++i) {
        float t = light_hit(light_source_of(i), ray.origin, ray.direction);
        if (t < light_t) {
            nearest = int(i);
            light_t = t;
        }
    }
    return nearest;
}

// What the light or the sky that a path's ray met gives, weighed against light sampling
// from the last vertex (`arrival_*`; unweighted from the camera or a delta lobe).
vec3 emitted(int light, float light_t, Ray ray, vec3 arrival_origin, float arrival_pdf, bool arrival_unweighted) {
    float choice = 1.0 / float(max(emitter_count(), 1u));
    vec3 radiance;
    float density;
    if (light >= 0) {
        LightSource source = light_source_of(uint(light));
        radiance = light_emitted(source, ray.direction);
        density = light_pdf(source, arrival_origin, ray.direction, light_t);
    } else {
        radiance = sky(ray.direction);
        density = sky_pdf(ray.direction);
    }
    return arrival_unweighted ? radiance : radiance * power_heuristic(arrival_pdf, choice * density);
}

vec3 path_trace(Ray ray, RandomSequence random, bool record, uint pixel_index) {
    vec3 radiance = vec3(0.0);
    vec3 throughput = vec3(1.0);
    vec3 arrival_origin = ray.origin;
    float arrival_pdf = 0.0;
    bool arrival_unweighted = true;
    for (uint depth = 0u; depth < settings.max_depth; ++depth) {
        random.dimension = depth * BOUNCE_DIMENSIONS;
        COUNT_RAY();
        trace_segment(ray, 0.0);
        bool first = record && depth == 0u;
        bool hit = payload.instance != MISS_ID;
        float light_t;
        int light = light_on(ray, hit ? payload.t : INFINITE_T, light_t);
        if (light >= 0 || !hit) {
            if (first) {
                record_aov(pixel_index, vec3(0.0), -1.0, MISS_ID, MISS_ID);
            }
            radiance += throughput * emitted(light, light_t, ray, arrival_origin, arrival_pdf, arrival_unweighted);
            break;
        }
        vec3 normal = payload.normal_or_background;
        vec3 position = ray_at(ray, payload.t);
        float clearance = payload.clearance;
        ObjectRecord object = objects[payload.instance];
        bool point_colors = object.specular_shininess_reflect_colors.w != 0.0;
        vec3 base_color = point_colors ? unpack_color(payload.color_rgba8) : object.diffuse_ambient.rgb;
        Bsdf bsdf = Bsdf(object.bsdf_kind, base_color, object.roughness, object.emission_ior.a);
        if (first) {
            record_aov(pixel_index, face_forward(normal, ray.direction), payload.t, object.object_index,
                       payload.primitive);
            // The albedo AOV in half floats, where the Whitted path leaves zeros.
            pixels[pixel_index].ids.zw = uvec2(packHalf2x16(base_color.rg), packHalf2x16(vec2(base_color.b, 0.0)));
        }
        radiance += throughput * surface_emission(object.emission_ior.rgb, clearance, normal, ray, payload.t,
                                                  arrival_pdf, arrival_unweighted);
        if (depth + 1u >= settings.max_depth) {
            break;
        }
        vec3 shading = bsdf_is_two_sided(bsdf) ? face_forward(normal, ray.direction) : normal;
        vec3 wo = to_local(-ray.direction, shading);
        radiance += throughput * direct_light(position, normal, clearance, bsdf, shading, wo, random);
        vec2 u = random_next2(random);
        BsdfSample drawn = bsdf_sample(bsdf, wo, vec3(u, random_next(random)));
        if (is_black(drawn.weight)) {
            break;
        }
        throughput *= drawn.weight;
        vec3 direction = to_world(drawn.direction, shading);
        arrival_origin = position;
        arrival_pdf = drawn.pdf;
        arrival_unweighted = drawn.delta;
        ray = Ray(leaving(position, normal, clearance, direction), direction);
        if (depth + 1u >= ROULETTE_AFTER) {
            float survival = min(max(throughput.x, max(throughput.y, throughput.z)), MAX_SURVIVAL);
            if (random_next(random) >= survival) {
                break;
            }
            throughput /= survival;
        }
    }
    return radiance;
}

#endif
