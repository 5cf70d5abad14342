//! Every `#include`-able GLSL snippet in `shaders/` compiles with glslang, wrapped in a
//! tiny compute shader that calls its functions (so their signatures are checked too).

use std::fs;
use std::path::{Path, PathBuf};

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    Compiler, CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage, SpirvVersion, Target,
    VulkanVersion,
};

fn shader_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders")
}

/// Resolves `#include "NAME"` from `shaders/`.
struct ShaderDirIncludes;

impl IncludeHandler for ShaderDirIncludes {
    fn include(&mut self, _: IncludeType, header: &str, _: &str, _: usize) -> Option<IncludeResult> {
        let data = fs::read_to_string(shader_dir().join(header)).ok()?;
        Some(IncludeResult { name: header.to_owned(), data })
    }
}

/// The maths snippets (twins of `src/*.rs`) and the body of a `main` that calls each one,
/// so that their signatures are checked, not just their syntax. The entry-point stages and
/// their own includes belong to the Vulkan crate's build, which compiles them.
const MATHS_SNIPPETS: &[(&str, &str)] = &[
    (
        "ray.glsl",
        "result = ray_at(Ray(vec3(0.0), vec3(1.0)), 2.0);",
    ),
    (
        "camera_ray.glsl",
        "Camera camera = Camera(vec3(0.0, 0.0, 5.0), vec3(0.0), vec3(0.0, 1.0, 0.0), 45.0);
             Ray ray = camera_ray(camera, uvec2(640u, 480u), gl_GlobalInvocationID.xy, sample_jitter(3u));
             result = ray.direction;",
    ),
    (
        "quadratic_roots.glsl",
        "vec2 roots; uint count = quadratic_roots(1.0, -4.0, 3.0, roots); result = vec3(roots, float(count));",
    ),
    (
        "patch_frame.glsl",
        "Patch hot_patch = decode_patch(PatchHot(0.0, 0.0, 0.0, 1.0, 0u, 0u, 0u, 0u));
             result = patch_direction_to_world(hot_patch, patch_to_local(hot_patch, vec3(1.0)));",
    ),
    (
        "unpacked_patch.glsl",
        "Patch unpacked = unpacked_patch(PatchUnpacked(vec4(0.0, 0.0, 0.0, 1.0), vec4(1.0, 0.0, 0.0, 0.5), vec4(0.0, 0.0, 1.0, 0.0), vec4(0.5)));
             result = patch_to_local(unpacked, vec3(1.0)) + vec3(unpacked.radii, unpacked.c5);",
    ),
    (
        "intersect_patch.glsl",
        "Patch hot_patch = decode_patch(PatchHot(0.0, 0.0, 0.0, 1.0, 0u, 0u, packHalf2x16(vec2(0.0, 0.5)), packHalf2x16(vec2(0.0, 0.5))));
             float t; vec2 uv;
             bool hit = intersect_patch(Ray(vec3(0.0, 0.0, 2.0), vec3(0.0, 0.0, -1.0)), hot_patch, 0.0, 1e30, ACCEPTANCE_DISK, t, uv);
             result = vec3(uv, hit ? t : -1.0);",
    ),
    (
        "patch_normal.glsl",
        "Patch hot_patch = decode_patch(PatchHot(0.0, 0.0, 0.0, 1.0, 0u, 0u, packHalf2x16(vec2(0.0, 0.5)), packHalf2x16(vec2(0.0, 0.5))));
             result = patch_normal(hot_patch, vec2(0.5, 0.25));",
    ),
    (
        "interpolate_color.glsl",
        "HotPatches hot = HotPatches(uvec2(64u, 0u));
             ColdPatches cold = ColdPatches(uvec2(128u, 0u));
             ColorNeighbors neighbors = ColorNeighbors(uvec2(0u));
             uint packed = interpolate_color(vec3(0.5, 0.0, 0.0), 3u, hot, cold, neighbors);
             result = color_from_rgba8(packed) + vec3(color_weight(0.2, 1.0));",
    ),
    (
        "face_forward.glsl",
        "result = face_forward(vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0));",
    ),
    (
        "phong.glsl",
        "PhongSurface surface = PhongSurface(vec3(0.8), 0.3, 32.0);
             result = phong(vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), vec3(1.0), surface);",
    ),
    (
        "self_clearance.glsl",
        "result = vec3(self_clearance(0.5), path_ray_offset(0.5, 1e-4), 0.0);",
    ),
    (
        "srgb_encode.glsl",
        "result = vec3(float(srgb_encode(0.5)), float(srgb_encode_rgba8(vec3(1.0, 0.5, 0.0)) >> 24), 0.0);",
    ),
    (
        "background.glsl",
        "result = background(vec3(0.0, 1.0, 0.0), vec3(0.2, 0.4, 1.0), vec3(1.0));",
    ),
    (
        "random_sequence.glsl",
        "RandomSequence sequence = random_sequence(7u, gl_GlobalInvocationID.xy, 3u);
             result = vec3(random_next(sequence), random_next2(sequence));",
    ),
    (
        "sampling.glsl",
        "vec3 d = to_world(cosine_hemisphere(vec2(0.3, 0.6)), vec3(0.0, 1.0, 0.0));
             result = d + uniform_sphere(vec2(0.1)) + uniform_cone(vec2(0.2), 0.9)
                 + vec3(cosine_hemisphere_pdf(d.z), uniform_cone_pdf(0.9), power_heuristic(1.0, UNIFORM_SPHERE_PDF))
                 + to_local(d, vec3(0.0, 0.0, -1.0));",
    ),
    (
        "fresnel.glsl",
        "vec3 refracted; bool through = refract_direction(vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), 1.5, refracted);
             result = refracted + fresnel_schlick(0.5, vec3(0.9)) + vec3(fresnel_dielectric(1.0, 1.5), float(through), 0.0);",
    ),
    (
        "microfacet.glsl",
        "vec3 m = ggx_sample_visible(vec3(0.0, 0.6, 0.8), 0.3, vec2(0.4, 0.7));
             result = m * ggx_d(m, 0.3) * smith_g2(m, m, 0.3) + vec3(ggx_visible_pdf(vec3(0.0, 0.0, 1.0), m, 0.3));",
    ),
    (
        "bsdf.glsl",
        "Bsdf bsdf = Bsdf(BSDF_PLASTIC, vec3(0.8), 0.2, 1.5);
             BsdfSample s = bsdf_sample(bsdf, vec3(0.0, 0.0, 1.0), vec3(0.1, 0.2, 0.3));
             result = s.weight + bsdf_eval(bsdf, vec3(0.0, 0.0, 1.0), s.direction)
                 + vec3(bsdf_pdf(bsdf, vec3(0.0, 0.0, 1.0), s.direction), float(bsdf_is_two_sided(bsdf)), float(bsdf_samples_lights(bsdf)));",
    ),
    (
        "light_source.glsl",
        "LightSource light = LightSource(LIGHT_QUAD, vec3(0.0, 0.0, 2.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), 0.0, vec3(1.0));
             LightSample s = light_sample(light, vec3(0.0), vec2(0.5));
             result = s.radiance * s.pdf + light_emitted(light, s.direction) + vec3(light_hit(light, vec3(0.0), s.direction), light_pdf(light, vec3(0.0), s.direction, s.distance), float(light_is_delta(light)));",
    ),
    (
        "environment_map.glsl",
        "EnvironmentMap map = EnvironmentMap(8u, 4u, 0.25);
             LightSample s = environment_sample(map, vec2(0.3, 0.6));
             result = s.radiance * s.pdf + environment_radiance(map, s.direction)
                 + vec3(environment_pdf(map, s.direction), environment_uv(map, s.direction));",
    ),
    (
        "emissive_triangles.glsl",
        "EmissiveTriangles triangles = EmissiveTriangles(2u, 3.0);
             LightSample s = emissive_sample(triangles, 0.4, vec2(0.3, 0.6), vec3(0.0));
             result = s.radiance * s.pdf + vec3(emissive_pdf(triangles, s.distance, 0.5));",
    ),
];

/// What a snippet needs its includer to define first: where its data lies.
const PRELUDES: &[(&str, &str)] = &[
    (
        "emissive_triangles.glsl",
        "layout(std430, binding = 1) readonly buffer Records { vec4 records[]; };
layout(std430, binding = 2) readonly buffer Areas { float areas[]; };
#define EMISSIVE_RECORD(i) records[i]
#define EMISSIVE_DISTRIBUTION(i) areas[i]",
    ),
    (
        "environment_map.glsl",
        "layout(std430, binding = 1) readonly buffer Texels { vec4 texels[]; };
layout(std430, binding = 2) readonly buffer Distribution { float distribution[]; };
#define ENVIRONMENT_TEXEL(i) texels[i]
#define ENVIRONMENT_DISTRIBUTION(i) distribution[i]",
    ),
];

fn wrapper(snippet: &str, calls: &str) -> String {
    let prelude = PRELUDES.iter().find(|(name, _)| *name == snippet).map_or("", |(_, prelude)| prelude);
    format!(
        "#version 460
#extension GL_GOOGLE_include_directive : require
{prelude}
#include \"{snippet}\"
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) buffer Output {{ vec3 result; }};
void main() {{
    {}
}}
",
        calls
    )
}

fn compile(snippet: &str, calls: &str) -> Result<Vec<u32>, String> {
    let compiler = Compiler::acquire().ok_or("glslang failed to initialise")?;
    let source = ShaderSource::from(wrapper(snippet, calls));
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan { version: VulkanVersion::Vulkan1_2, spirv_version: SpirvVersion::SPIRV1_5 },
        version_profile: None,
        ..CompilerOptions::default()
    };
    let mut includes = ShaderDirIncludes;
    let input = ShaderInput::new(
        &source,
        ShaderStage::Compute,
        &options,
        None::<&[(&str, Option<&str>)]>,
        Some(&mut includes),
    )
    .map_err(|e| e.to_string())?;
    let shader = compiler.create_shader(input).map_err(|e| e.to_string())?;
    shader.compile().map_err(|e| e.to_string())
}

#[test]
fn every_snippet_compiles_in_a_compute_shader_that_calls_it() {
    let failures: Vec<String> = MATHS_SNIPPETS
        .iter()
        .filter_map(|(name, calls)| compile(name, calls).err().map(|error| format!("{name}:\n{error}")))
        .collect();
    assert!(failures.is_empty(), "GLSL snippets failed to compile:\n{}", failures.join("\n"));
}

#[test]
fn a_broken_snippet_is_reported() {
    // Guards the test above against passing vacuously: a missing file, or a call that
    // does not match a signature, must fail.
    assert!(compile("no_such_snippet.glsl", "").is_err());
    assert!(compile("phong.glsl", "result = phong(vec3(1.0));").is_err());
}
