//! Compiles every shader stage in `shaders/` to SPIR-V 1.4 (Vulkan 1.2) into `OUT_DIR`,
//! where `src/shaders.rs` embeds it with `include_bytes!`. Includes resolve against this
//! crate's `shaders/` (the pipeline's interface) and then the kernels' GLSL twins. The
//! probes in `shaders/twins/` (one compute stage per group of twins, which the twin tests
//! run against the Rust twins) come out as `twins/NAME.comp.spv`.

use std::path::PathBuf;

use glslang::include::{IncludeHandler, IncludeResult, IncludeType};
use glslang::{
    CompilerOptions, ShaderInput, ShaderSource, ShaderStage, SourceLanguage, SpirvVersion, Target,
    VulkanVersion,
};

/// The entry points this crate's pipeline uses, with their stages, and the probe that the
/// interface tests reflect on (`src/spirv_reflection.rs`).
const ENTRY_POINTS: &[(&str, ShaderStage)] = &[
    ("primary.rgen", ShaderStage::RayGeneration),
    ("ray_list.rgen", ShaderStage::RayGeneration),
    ("background.rmiss", ShaderStage::Miss),
    ("shadow.rmiss", ShaderStage::Miss),
    ("patch.rint", ShaderStage::Intersect),
    ("patch.rchit", ShaderStage::ClosestHit),
    ("triangle.rchit", ShaderStage::ClosestHit),
    ("interface_probe.rgen", ShaderStage::RayGeneration),
];

/// Entry points compiled again with defines (separated by spaces), as `(source, defines,
/// output name)`: the benchmark's ray-counting ray generation, the hit-reordering one, the
/// path integrator's with and without ray counting, the counting pipeline's intersection, the
/// hit group of boxes of several patches (`BlasLayout::PatchGroups`), counting or not, and
/// that of unpacked hot records (`HotRecords::Unpacked`), counting or not.
const VARIANTS: &[(&str, ShaderStage, &str, &str)] = &[
    ("primary.rgen", ShaderStage::RayGeneration, "COUNT_RAYS", "primary_counting.rgen"),
    ("primary.rgen", ShaderStage::RayGeneration, "REORDER_HITS", "primary_reordering.rgen"),
    ("primary.rgen", ShaderStage::RayGeneration, "PATH_TRACING", "path.rgen"),
    ("primary.rgen", ShaderStage::RayGeneration, "PATH_TRACING COUNT_RAYS", "path_counting.rgen"),
    ("patch.rint", ShaderStage::Intersect, "COUNT_RAYS", "patch_counting.rint"),
    ("patch.rint", ShaderStage::Intersect, "PATCH_GROUPS", "patch_groups.rint"),
    ("patch.rint", ShaderStage::Intersect, "PATCH_GROUPS COUNT_RAYS", "patch_groups_counting.rint"),
    ("patch.rchit", ShaderStage::ClosestHit, "PATCH_GROUPS", "patch_groups.rchit"),
    ("patch.rint", ShaderStage::Intersect, "UNPACKED_RECORDS", "patch_unpacked.rint"),
    ("patch.rint", ShaderStage::Intersect, "UNPACKED_RECORDS COUNT_RAYS", "patch_unpacked_counting.rint"),
    ("patch.rchit", ShaderStage::ClosestHit, "UNPACKED_RECORDS", "patch_unpacked.rchit"),
];

/// Resolves `#include "NAME"` against the given folders, in order.
struct ShaderFolderIncludes {
    folders: Vec<PathBuf>,
}

impl IncludeHandler for ShaderFolderIncludes {
    fn include(
        &mut self,
        _ty: IncludeType,
        header: &str,
        _includer: &str,
        _depth: usize,
    ) -> Option<IncludeResult> {
        let path = self.folders.iter().map(|folder| folder.join(header)).find(|path| path.is_file())?;
        let data = std::fs::read_to_string(&path).ok()?;
        Some(IncludeResult { name: path.display().to_string(), data })
    }
}

fn compile(
    folders: &[PathBuf],
    name: &str,
    stage: ShaderStage,
    define: Option<&str>,
) -> Result<Vec<u32>, String> {
    let path = folders[0].join(name);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let source = ShaderSource::from(text);
    let options = CompilerOptions {
        source_language: SourceLanguage::GLSL,
        target: Target::Vulkan { version: VulkanVersion::Vulkan1_2, spirv_version: SpirvVersion::SPIRV1_4 },
        version_profile: None,
        ..CompilerOptions::default()
    };
    let mut includes = ShaderFolderIncludes { folders: folders.to_vec() };
    let defines: Vec<(&str, Option<&str>)> =
        define.into_iter().flat_map(str::split_whitespace).map(|name| (name, None)).collect();
    let input = ShaderInput::new(&source, stage, &options, Some(&defines[..]), Some(&mut includes))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let compiler = glslang::Compiler::acquire().ok_or("glslang failed to initialise")?;
    let shader = compiler.create_shader(input).map_err(|e| format!("{}: {e}", path.display()))?;
    shader.compile().map_err(|e| format!("{}: {e}", path.display()))
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let twins = manifest.join("shaders/twins");
    let folders = [manifest.join("shaders"), twins.clone(), PathBuf::from(pointray_kernels::SHADER_FOLDER)];
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::create_dir_all(out.join("twins")).expect("OUT_DIR is writable");
    for folder in &folders {
        println!("cargo:rerun-if-changed={}", folder.display());
        for entry in std::fs::read_dir(folder).into_iter().flatten().flatten() {
            println!("cargo:rerun-if-changed={}", entry.path().display());
        }
    }
    let mut failures = Vec::new();
    let plain = ENTRY_POINTS.iter().map(|&(name, stage)| (name, stage, None, name));
    let variants = VARIANTS.iter().map(|&(name, stage, define, output)| (name, stage, Some(define), output));
    let probes = twin_probes(&twins);
    let probes = probes.iter().map(|name| (name.as_str(), ShaderStage::Compute, None, name.as_str()));
    for (name, stage, define, output) in plain.chain(variants).chain(probes) {
        match compile(&folders, name, stage, define) {
            Ok(words) => {
                let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                std::fs::write(out.join(format!("{output}.spv")), bytes).expect("OUT_DIR is writable");
            }
            Err(message) => failures.push(message),
        }
    }
    if !failures.is_empty() {
        panic!("shader compilation failed:\n{}", failures.join("\n"));
    }
}

/// The twin probes, as paths relative to `shaders/`: `twins/NAME.comp`.
fn twin_probes(folder: &std::path::Path) -> Vec<String> {
    let entries = std::fs::read_dir(folder).into_iter().flatten().flatten();
    let mut names: Vec<String> = entries
        .filter_map(|entry| entry.file_name().into_string().ok())
        .filter(|name| name.ends_with(".comp"))
        .map(|name| format!("twins/{name}"))
        .collect();
    names.sort();
    names
}
