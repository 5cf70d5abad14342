//! The scene file parser and loader on arbitrary text. Scenes that name no file and whose
//! procedural objects are small are loaded too (recentring, extents, grounds, cameras,
//! procedural prep). Any result is fine; a panic, or a loaded scene with a non-finite camera or
//! transform, is not.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use pointray_scene::object_spec::ShapeSpec;
use pointray_scene::{LoadOptions, SceneFile, load_scene_file};

/// Larger procedural objects make each run too slow to fuzz.
const MAX_FUZZED_POINTS: u32 = 400;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(file) = SceneFile::parse(text, Path::new("fuzz/scene.toml")) else { return };
    let _ = file.input_files();
    let _ = file.render_settings();
    let small = file.objects.iter().all(|object| match object.shape {
        ShapeSpec::Points { .. } | ShapeSpec::Mesh { .. } => false,
        ShapeSpec::SpherePoints { count, .. } | ShapeSpec::TorusPoints { count, .. } => count <= MAX_FUZZED_POINTS,
        ShapeSpec::Ground { .. } => true,
    });
    if !small {
        return;
    }
    if let Ok(loaded) = load_scene_file(&file, &LoadOptions::default()) {
        let camera = &loaded.scene.camera;
        assert!(camera.position.is_finite() && camera.look_at.is_finite(), "{camera:?}");
        for object in &loaded.scene.objects {
            assert!(object.transform.is_finite(), "{}: {:?}", object.name, object.transform);
        }
    }
});
