//! Every input under `fuzz/regressions/scene_toml/` once broke the loader (see
//! `fuzz/README.md`): each must now load to finite numbers or fail with an error naming it.

use std::path::Path;

use pointray_scene::{LoadOptions, SceneFile, load_scene_file};

#[test]
fn every_scene_regression_loads_finite_or_fails_clearly() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions/scene_toml");
    let mut seen = 0;
    for entry in std::fs::read_dir(&folder).unwrap().flatten() {
        seen += 1;
        let text = std::fs::read_to_string(entry.path()).unwrap();
        let loaded = SceneFile::parse(&text, &entry.path())
            .and_then(|file| load_scene_file(&file, &LoadOptions::default()));
        match loaded {
            Ok(loaded) => {
                let camera = loaded.scene.camera;
                assert!(
                    camera.position.is_finite() && camera.look_at.is_finite(),
                    "{:?}: {camera:?}",
                    entry.path()
                );
                assert!(loaded.scene.objects.iter().all(|o| o.transform.is_finite()), "{:?}", entry.path());
            }
            Err(error) => assert!(error.to_string().contains("crash-"), "{error}"),
        }
    }
    assert!(seen > 0, "the regressions are in {}", folder.display());
}
