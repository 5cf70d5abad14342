//! The scene file: every example parses, and typos and bad values fail with messages that name
//! the file and the key.

use std::path::{Path, PathBuf};

use pointray_patches::PrepSettings;
use pointray_scene::object_spec::ShapeSpec;
use pointray_scene::scene_file::{BackgroundSpec, LightSpec};
use pointray_scene::{HotRecords, Integrator, SceneError, SceneFile};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

pub fn parse(text: &str) -> Result<SceneFile, SceneError> {
    SceneFile::parse(text, Path::new("test/scene.toml"))
}

pub fn error_message(text: &str) -> String {
    parse(text).expect_err("the scene should be rejected").to_string()
}

const MINIMAL_OBJECT: &str = "[[objects]]\ntype = \"sphere_points\"\nradius = 1.0\ncount = 100\n";

#[test]
fn every_example_scene_parses() {
    let mut names: Vec<String> = std::fs::read_dir(scenes_dir())
        .expect("scenes/ exists")
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".toml"))
        .collect();
    names.sort();
    for expected in
        ["bunny_floor.toml", "bunny_mesh_floor.toml", "demo.toml", "dragon_floor.toml", "horse_floor.toml"]
    {
        assert!(names.iter().any(|n| n == expected), "scenes/{expected} is missing");
    }
    for name in names {
        let file = SceneFile::read(&scenes_dir().join(&name)).unwrap_or_else(|e| panic!("{e}"));
        assert!(file.camera.is_some(), "{name}: the examples frame their models explicitly");
        assert_eq!(file.lights.len(), 1, "{name}: one light");
        assert!(!file.objects.is_empty(), "{name}: has objects");
        let ground = file.objects.iter().find(|o| matches!(o.shape, ShapeSpec::Ground { .. }));
        if file.render.integrator == Some(Integrator::Path) {
            // Path-traced examples give every surface a BSDF of its own.
            assert!(
                file.objects.iter().all(|o| o.material.bsdf.is_some()),
                "{name}: every object has a bsdf"
            );
        } else {
            let reflectivity = ground.and_then(|g| g.material.reflectivity).unwrap_or(0.0);
            assert!(reflectivity > 0.0, "{name}: the floor reflects");
        }
    }
}

#[test]
fn data_paths_in_examples_point_into_the_checkouts_data_folder() {
    let names =
        ["bunny_floor.toml", "horse_floor.toml", "dragon_floor.toml", "bunny_mesh_floor.toml", "autzen.toml"];
    for name in names {
        let file = SceneFile::read(&scenes_dir().join(name)).unwrap();
        let paths: Vec<&Path> = file
            .objects
            .iter()
            .filter_map(|o| match &o.shape {
                ShapeSpec::Points { path, .. } | ShapeSpec::Mesh { path } => Some(path.as_path()),
                _ => None,
            })
            .collect();
        assert_eq!(paths.len(), 1, "{name}");
        assert!(paths[0].starts_with("../data"), "{name}: {}", paths[0].display());
        let resolved = file.resolve(paths[0]);
        assert!(resolved.is_file(), "{name}: {} is not in the checkout", resolved.display());
    }
}

#[test]
fn a_full_scene_parses_into_the_expected_values() {
    let file = parse(
        r#"
        background = { top = [0.5, 0.6, 0.7], bottom = [1.0, 1.0, 1.0] }
        [camera]
        position = [0, 1, 5]
        look_at = [0, 0, 0]
        vfov_degrees = 30
        [render]
        width = 320
        spp = 4
        patches_per_box = 4
        hot_records = "packed"
        [[lights]]
        type = "directional"
        direction = [0, -2, 0]
        intensity = 0.5
        [[objects]]
        type = "points"
        path = "models/a.ply"
        prep = { k = 12 }
        [objects.material]
        reflectivity = 0.25
        use_point_colors = true
        "#,
    )
    .unwrap();
    let camera = file.camera.as_ref().unwrap();
    assert_eq!(camera.up, [0.0, 1.0, 0.0], "default up");
    assert_eq!(camera.vfov_degrees, 30.0);
    assert_eq!(file.render.width, Some(320));
    assert_eq!(file.render.height, None);
    assert_eq!(file.render.spp, Some(4));
    assert_eq!(file.render.patches_per_box, Some(4));
    assert_eq!(file.render.hot_records, Some(HotRecords::Packed));
    assert!(matches!(file.background, Some(BackgroundSpec::Gradient(_))));
    assert_eq!(
        file.lights[0],
        LightSpec::Directional { direction: [0.0, -2.0, 0.0], color: [1.0; 3], intensity: 0.5 }
    );
    assert_eq!(
        file.objects[0].shape,
        ShapeSpec::Points {
            path: "models/a.ply".into(),
            prep: Some(PrepSettings { k: 12, ..PrepSettings::default() }),
            columns: None
        }
    );
    assert_eq!(file.objects[0].material.use_point_colors, Some(true));
    assert_eq!(file.resolve(Path::new("models/a.ply")), Path::new("test/models/a.ply"));
    assert_eq!(file.resolve(Path::new("/abs/a.ply")), Path::new("/abs/a.ply"));
}

#[test]
fn unknown_keys_are_errors_naming_the_file_and_the_key() {
    let cases = [
        ("[camera]\nposition = [0,0,1]\nlook_at = [0,0,0]\nfov = 40\n", "fov"),
        ("colour = [1, 1, 1]\n", "colour"),
        ("[[lights]]\ntype = \"point\"\nposition = [0,1,0]\nintensty = 2\n", "intensty"),
        ("[render]\nsamples = 4\n", "samples"),
        ("[[objects]]\ntype = \"mesh\"\npath = \"a.ply\"\nradius = 2\n", "radius"),
        ("[[objects]]\ntype = \"ground\"\n[objects.material]\nshinyness = 3\n", "shinyness"),
        ("[[objects]]\ntype = \"ground\"\n[objects.transform]\ntranslation = [0,0,0]\n", "translation"),
        (
            "[[objects]]\ntype = \"ground\"\n[objects.transform]\nrotate = { axis = [0,1,0], degrees = 5, extra = 1 }\n",
            "extra",
        ),
        ("background = { top = [1,1,1], bottom = [0,0,0], middle = [1,0,0] }\n", "middle"),
    ];
    for (text, key) in cases {
        let message = error_message(text);
        assert!(message.starts_with("test/scene.toml"), "{message}");
        assert!(message.contains(key), "message for `{key}` does not name it: {message}");
    }
}

#[test]
fn unknown_types_and_wrong_value_types_are_errors() {
    let message = error_message("[[objects]]\ntype = \"teapot\"\n");
    assert!(message.contains("teapot"), "{message}");
    let message = error_message("[[lights]]\ntype = \"spot\"\nposition = [0,0,0]\n");
    assert!(message.contains("spot"), "{message}");
    let message = error_message("[render]\nwidth = \"wide\"\n");
    assert!(message.contains("width") || message.contains("wide"), "{message}");
    let message = error_message("[[objects]]\ntype = \"mesh\"\n");
    assert!(message.contains("path"), "a missing required key is named: {message}");
    let message = error_message("[[objects]]\ntype = \"ground\"\n[objects.transform]\nscale = \"big\"\n");
    assert!(message.contains("scale") && message.contains("a number"), "{message}");
}

#[test]
fn bad_values_are_errors_naming_the_key() {
    let object = |extra: &str| format!("{MINIMAL_OBJECT}{extra}");
    let cases = [
        ("[camera]\nposition = [0,0,0]\nlook_at = [0,0,0]\n".to_string(), "camera.look_at"),
        ("[camera]\nposition = [0,1,0]\nlook_at = [0,0,0]\n".to_string(), "camera.up"),
        (
            "[camera]\nposition = [0,0,1]\nlook_at = [0,0,0]\nvfov_degrees = 180\n".to_string(),
            "camera.vfov_degrees",
        ),
        (
            "[[lights]]\ntype = \"point\"\nposition = [0,1,0]\nintensity = -1\n".to_string(),
            "lights[0].intensity",
        ),
        ("[[lights]]\ntype = \"directional\"\ndirection = [0,0,0]\n".to_string(), "lights[0].direction"),
        (
            "[[lights]]\ntype = \"point\"\nposition = [0,1,0]\ncolor = [1,-1,1]\n".to_string(),
            "lights[0].color",
        ),
        ("background = [0.5, -0.1, 0]\n".to_string(), "background"),
        ("background = { map = \"sky.exr\", intensity = -1.0 }\n".to_string(), "background.intensity"),
        ("background = { sun_elevation_degrees = 95.0 }\n".to_string(), "background.sun_elevation_degrees"),
        (
            "background = { sun_elevation_degrees = 30.0, sun_radius_degrees = 0.0 }\n".to_string(),
            "background.sun_radius_degrees",
        ),
        ("[render]\nwidth = 0\n".to_string(), "render.width"),
        ("[render]\nmax_depth = 0\n".to_string(), "render.max_depth"),
        ("[render]\npatches_per_box = 65\n".to_string(), "render.patches_per_box"),
        (object("[objects.material]\nreflectivity = 1.5\n"), "objects[0].material.reflectivity"),
        (object("[objects.material]\nambient = -0.1\n"), "objects[0].material.ambient"),
        (object("[objects.transform]\nscale = 0.0\n"), "objects[0].transform.scale"),
        (object("[objects.transform]\nscale = [1.0, 0.0, 1.0]\n"), "objects[0].transform.scale"),
        (
            object("[objects.transform]\nrotate = { axis = [0,0,0], degrees = 10 }\n"),
            "objects[0].transform.rotate.axis",
        ),
        (
            "[[objects]]\ntype = \"sphere_points\"\nradius = -1.0\ncount = 100\n".to_string(),
            "objects[0].radius",
        ),
        ("[[objects]]\ntype = \"sphere_points\"\nradius = 1.0\ncount = 3\n".to_string(), "objects[0].count"),
        (
            "[[objects]]\ntype = \"torus_points\"\nmajor_radius = 0.2\nminor_radius = 0.3\ncount = 100\n"
                .to_string(),
            "objects[0].minor_radius",
        ),
        ("[[objects]]\ntype = \"ground\"\nauto = true\nheight = 1.0\n".to_string(), "objects[0].height"),
        ("[[objects]]\ntype = \"ground\"\nsize = 0.0\n".to_string(), "objects[0].size"),
        (
            "[[objects]]\ntype = \"points\"\npath = \"a.ply\"\nprep = { k = 2 }\n".to_string(),
            "objects[0].prep.k",
        ),
        ("[[objects]]\ntype = \"mesh\"\npath = \"\"\n".to_string(), "objects[0].path"),
    ];
    for (text, key) in cases {
        match parse(&text) {
            Err(SceneError::Invalid { path, key: found, problem }) => {
                assert_eq!(path, Path::new("test/scene.toml"));
                assert_eq!(found, key, "problem: {problem}");
            }
            other => panic!("expected an invalid value at {key}, got {other:?}"),
        }
    }
}

#[test]
fn a_syntax_error_names_the_file_and_the_line() {
    let message = error_message("[camera]\nposition = [0, 0,\n");
    assert!(message.starts_with("test/scene.toml"), "{message}");
    assert!(message.contains("line 2") || message.contains("2 |"), "{message}");
}

#[test]
fn an_unreadable_scene_file_is_named() {
    let missing = Path::new("does/not/exist.toml");
    let message = SceneFile::read(missing).expect_err("missing file").to_string();
    assert!(message.contains("does/not/exist.toml"), "{message}");
}

#[test]
fn an_empty_file_is_a_valid_empty_scene() {
    let file = parse("").unwrap();
    assert_eq!(file.render, Default::default());
    assert!(file.objects.is_empty() && file.lights.is_empty());
}
