//! Requests too large for memory are refused at once, with what would fit, before anything
//! is allocated; settings out of range are refused whether they come from a flag or a file.

use crate::common::{pointray_in, write_grid_ply, write_points_scene};

#[test]
fn an_image_too_large_for_memory_says_what_fits() {
    let dir = tempfile::tempdir().unwrap();
    write_points_scene(dir.path(), "scene.toml", "missing.ply");
    let (ok, _, stderr) = pointray_in(
        dir.path(),
        &["render", "scene.toml", "-o", "out.png", "--width", "65536", "--height", "65536"],
    );
    assert!(!ok && stderr.contains("a 65536x65536 image") && stderr.contains("e.g. "), "{stderr}");
    let (ok, _, stderr) = pointray_in(
        dir.path(),
        &["render", "scene.toml", "-o", "out.png", "--width", "100000", "--height", "100000"],
    );
    assert!(!ok && stderr.contains("must be between 1 and 65536"), "{stderr}");
}

#[test]
fn sample_refuses_counts_beyond_memory_without_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("mesh.ply"));
    for count in ["10000000000", "18446744073709551615"] {
        let (ok, _, stderr) =
            pointray_in(dir.path(), &["sample", "mesh.ply", "-o", "out.ply", "--count", count]);
        assert!(!ok && !stderr.contains("panicked"), "{stderr}");
        assert!(stderr.contains("of memory") && stderr.contains("at most about"), "{stderr}");
    }
}

#[test]
fn a_procedural_object_beyond_memory_is_refused_by_key() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, "[[objects]]\ntype = \"sphere_points\"\nradius = 1.0\ncount = 4000000000\n")
        .unwrap();
    let (ok, _, stderr) =
        pointray_in(dir.path(), &["render", "scene.toml", "-o", "out.png", "--backend", "cpu"]);
    assert!(!ok && stderr.contains("objects[0]") && stderr.contains("at most about"), "{stderr}");
}

#[test]
fn flags_and_files_share_each_settings_check() {
    let dir = tempfile::tempdir().unwrap();
    write_points_scene(dir.path(), "scene.toml", "missing.ply");
    for (flag, value) in [("--max-depth", "0"), ("--spp", "0"), ("--width", "0"), ("--spp", "4000000000")] {
        let (ok, _, stderr) =
            pointray_in(dir.path(), &["render", "scene.toml", "-o", "out.png", flag, value]);
        assert!(
            !ok && stderr.contains(flag) && stderr.contains("must be between 1 and"),
            "{flag} {value}: {stderr}"
        );
        let key = flag.trim_start_matches("--").replace('-', "_");
        std::fs::write(dir.path().join("file.toml"), format!("[render]\n{key} = {value}\n")).unwrap();
        let (ok, _, stderr) = pointray_in(dir.path(), &["render", "file.toml", "-o", "out.png"]);
        assert!(!ok && stderr.contains(&format!("render.{key}")), "{key} = {value}: {stderr}");
        assert!(stderr.contains("must be between 1 and"), "{stderr}");
    }
    let (ok, _, stderr) =
        pointray_in(dir.path(), &["prep", "missing.ply", "-o", "out.patches", "--sensor", "nan,0,0"]);
    assert!(!ok && stderr.contains("--sensor") && stderr.contains("finite"), "{stderr}");
    let (ok, _, stderr) = pointray_in(dir.path(), &["prep", "missing.ply", "-o", "out.patches", "--k", "2"]);
    assert!(!ok && stderr.contains("--k: must be between 3 and"), "{stderr}");
}
