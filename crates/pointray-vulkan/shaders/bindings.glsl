// The ray-tracing pipeline's resources, shared by its entry points. Mirrored on the Rust
// side in `src/gpu_records.rs` (records and codes) and `src/pipeline.rs` (bindings); the
// tests of both check them against the compiled SPIR-V (`src/spirv_reflection.rs`).
#ifndef POINTRAY_BINDINGS_GLSL
#define POINTRAY_BINDINGS_GLSL

#extension GL_EXT_ray_tracing : require
#extension GL_EXT_buffer_reference : require

#include "layout.glsl"
#include "patch_buffers.glsl"

// Hot and cold records together, for BufferLayout::Combined: 44 bytes, no padding.
struct PatchCombined {
    PatchHot hot;
    PatchCold cold;
};

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer CombinedPatches { PatchCombined records[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MeshVertices { vec4 positions[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer MeshIndices { uint indices[]; };

// One per TLAS instance, indexed by gl_InstanceCustomIndexEXT: a mesh, a point set, or one
// tile of a large point set (a run of its patches with a BLAS of its own; the tiles of a set
// share its buffers). Addresses that the object's kind does not use are zero; only the hit
// group of that kind dereferences them.
struct ObjectRecord {
    HotPatches hot;
    ColdPatches cold;
    CombinedPatches combined;
    MeshVertices vertices;
    MeshIndices indices;
    ColorNeighbors color_neighbors;         // 0 where the points have no colours (interpolate_color.glsl)
    vec4 diffuse_ambient;                   // rgb = diffuse colour, a = ambient
    vec4 specular_shininess_reflect_colors; // x = specular, y = shininess, z = reflectivity, w = use point colours
    uint object_index;                      // the object's index in the scene (the instance AOV)
    uint first_patch;                       // the patch index of the tile's primitive 0
    uint bsdf_kind;                         // the path integrator's BSDF (BSDF_* of bsdf.glsl)
    float roughness;                        // its GGX alpha
    vec4 emission_ior;                      // rgb = emitted radiance, a = index of refraction
    uint patch_end;                         // one past the tile's last patch
    uint patches_per_box;                   // consecutive patches one box of its BLAS bounds
};

// What the patch intersection shader hands the closest-hit shader: which patch of the box
// it hit (its index in the set) and the hit's (u, v) on it.
struct PatchHit {
    vec2 uv;
    uint patch_index;
};

// Whitted: position_or_direction.xyz = a point light's position (w = 0) or a directional
// light's travel direction (w = 1), shining whitted_radiance; area lights come as points at
// their centres. The path integrator reads the light as light_source.glsl's LightSource:
// kind in radiance.a, position, edges and radius in the rest.
struct LightRecord {
    vec4 position_or_direction;
    vec4 whitted_radiance; // rgb = colour * intensity, with no falloff
    vec4 radiance;      // rgb = LightSource.radiance, a = LIGHT_* of light_source.glsl
    vec4 origin_radius; // xyz = LightSource.position, w = LightSource.radius
    vec4 edge_u;        // xyz = LightSource.edge_u
    vec4 edge_v;        // xyz = LightSource.edge_v
};

// The background's map, where it has one (environment_map.glsl reads it through these).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EnvironmentTexels { vec4 texels[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer EnvironmentDistribution { float values[]; };
// The emissive mesh triangles' table, where there are any (emissive_triangles.glsl reads it).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EmissiveRecords { vec4 records[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer EmissiveDistribution { float values[]; };

layout(set = 0, binding = 0) uniform accelerationStructureEXT scene_tlas;

layout(set = 0, binding = 1, std140) uniform FrameUniforms {
    vec4 camera_position_fov; // xyz = position, w = vertical fov in degrees
    vec4 camera_look_at;
    vec4 camera_up;
    vec4 background_top;      // a solid background has top == bottom
    vec4 background_bottom;
    uint light_count;
    float ray_epsilon;
    uint sky_lit;             // the background lights the scene (the path integrator draws it)
    uint sky_is_map;          // the background is the map below, not the gradient above
    EnvironmentTexels sky_texels;
    EnvironmentDistribution sky_distribution;
    uint sky_width;
    uint sky_height;
    float sky_rotation;       // turns about +y
    uint emissive_count;      // emissive mesh triangles; 0: none, and no table
    EmissiveRecords emissive_records;
    EmissiveDistribution emissive_distribution;
    float emissive_total_area;
    uint pad0;
    uint pad1;
    uint pad2;
} frame;

#define ENVIRONMENT_TEXEL(i) frame.sky_texels.texels[i]
#define ENVIRONMENT_DISTRIBUTION(i) frame.sky_distribution.values[i]
#define EMISSIVE_RECORD(i) frame.emissive_records.records[i]
#define EMISSIVE_DISTRIBUTION(i) frame.emissive_distribution.values[i]

layout(set = 0, binding = 2, std430) readonly buffer Objects { ObjectRecord objects[]; };
layout(set = 0, binding = 3, std430) readonly buffer Lights { LightRecord lights[]; };

struct PixelRecord {
    vec4 color;
    vec4 normal_depth;   // face-forwarded world normal, depth (negative = miss)
    uvec4 ids;           // instance, primitive; the path integrator's albedo in half floats in zw
};
layout(set = 0, binding = 4, std430) writeonly buffer Pixels { PixelRecord pixels[]; };
// The display output: one sRGB8 RGBA pixel each (srgb_encode_rgba8), what a window shows.
layout(set = 0, binding = 5, std430) writeonly buffer DisplayPixels { uint display_pixels[]; };
// The display outputs' running sums: rgb = the pixel's colour summed over every sample since
// sample 0, so that a trace from settings.first_sample > 0 continues the ones before it.
layout(set = 0, binding = 6, std430) buffer Accumulation { vec4 accumulated[]; };

// A ray list (ray_list.rgen): each ray as traceRayEXT takes it, in the frame of the poses
// that place it in the scene (a sensor's); each pose, an affine map into the scene's frame
// by rows (scene = rows * (x, y, z, 1)); and what each ray met from each pose: its distance
// (negative on a miss), the object's index in the scene and the patch or triangle index
// (MISS_ID on a miss).
struct ListedRay {
    vec3 origin;
    float t_min;
    vec3 direction;
    float t_max;
};
struct RayPose {
    vec4 rows[3];
};
struct RayHit {
    float t;
    uint object_index;
    uint primitive;
};
layout(set = 0, binding = 7, std430) readonly buffer RayList { ListedRay listed_rays[]; };
layout(set = 0, binding = 8, std430) writeonly buffer RayHits { RayHit ray_hits[]; };
layout(set = 0, binding = 9, std430) readonly buffer RayPoses { RayPose ray_poses[]; };

// Which output a trace writes; the other is left untouched. The display output is sRGB8
// RGBA, or with blue in the low byte for B8G8R8A8 swapchains.
const uint OUTPUT_AOVS = 0u;
const uint OUTPUT_DISPLAY = 1u;
const uint OUTPUT_DISPLAY_BGRA = 2u;

const uint LAYOUT_SPLIT = 0u;
const uint LAYOUT_COMBINED = 1u;

// Small per-trace settings that the intersection shader reads on every call.
layout(push_constant) uniform TraceSettings {
    uint width;
    uint height;
    uint samples_per_pixel;
    uint max_depth;
    uint shadows;
    uint acceptance; // ACCEPTANCE_BOX or ACCEPTANCE_DISK of intersect_patch.glsl
    uint buffer_layout;
    uint output_kind; // OUTPUT_AOVS or OUTPUT_DISPLAY
    uint seed;        // the path integrator's random sequence (path.rgen)
    uint first_sample; // the trace takes samples first_sample .. first_sample + samples_per_pixel
} settings;

// A mesh's vertex and index, addressed as `record_address` explains.
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MeshVertexAt { vec4 position; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer MeshIndexAt { uint index; };

// The position of the vertex at `corner` of the object's index list.
vec3 mesh_vertex(ObjectRecord object, uint corner) {
    uint vertex = MeshIndexAt(record_address(uvec2(object.indices), corner, 4u)).index;
    return MeshVertexAt(record_address(uvec2(object.vertices), vertex, 16u)).position.xyz;
}

// A combined record, addressed as `record_address` explains.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer CombinedPatchAt { PatchCombined record; };

PatchHot load_hot(ObjectRecord object, uint patch_index) {
    if (settings.buffer_layout == LAYOUT_COMBINED) {
        uvec2 address = record_address(uvec2(object.combined), patch_index, PATCH_HOT_BYTES + PATCH_COLD_BYTES);
        return CombinedPatchAt(address).record.hot;
    }
    return hot_record(object.hot, patch_index);
}

// Patch `patch_index` of the object, from its hot record in the form that the including hit
// group reads: unpacked where it defines UNPACKED_RECORDS (`HotRecords::Unpacked`, which
// only split buffers take), else packed.
Patch load_patch(ObjectRecord object, uint patch_index) {
#ifdef UNPACKED_RECORDS
    return unpacked_patch(unpacked_record(object.hot, patch_index));
#else
    return decode_patch(load_hot(object, patch_index));
#endif
}

#endif
