//! No command writes over a file it reads: not the scene, not a points file, not through a
//! symlink or a hard link, and not through an AOV's name. Output paths are checked before
//! anything is loaded.

use std::path::Path;

use crate::common::{pointray_in, write_grid_ply, write_points_scene};

/// `pointray render INPUT -o OUTPUT` (and extra flags) in `dir`: it must fail, naming the
/// input, and leave every file in `dir` as it was.
fn assert_render_refuses(dir: &Path, scene: &str, output: &str, extra: &[&str]) {
    let before = snapshot(dir);
    let mut args = vec!["render", scene, "-o", output, "--backend", "cpu", "--width", "8", "--height", "8"];
    args.extend(extra);
    let (ok, _, stderr) = pointray_in(dir, &args);
    assert!(!ok, "render -o {output} must be refused");
    assert!(stderr.contains("refusing to write over the input file"), "{stderr}");
    assert_eq!(snapshot(dir), before, "render -o {output} changed the folder");
}

/// Every file's name and bytes, sorted.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|entry| {
            (
                entry.file_name().to_string_lossy().into_owned(),
                std::fs::read(entry.path()).unwrap_or_default(),
            )
        })
        .collect();
    files.sort();
    files
}

#[test]
fn render_refuses_to_overwrite_the_scene_and_its_points() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.png"));
    write_points_scene(dir.path(), "scene.toml", "grid.png");
    assert_render_refuses(dir.path(), "scene.toml", "grid.png", &[]);
    // A bare points file is the input itself.
    assert_render_refuses(dir.path(), "grid.png", "grid.png", &[]);
}

#[test]
fn render_refuses_an_aov_name_that_is_an_input() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("out.depth.exr"));
    write_points_scene(dir.path(), "scene.toml", "out.depth.exr");
    assert_render_refuses(dir.path(), "scene.toml", "out.png", &["--aovs"]);
}

#[cfg(unix)]
#[test]
fn render_refuses_links_to_an_input() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    std::os::unix::fs::symlink("grid.ply", dir.path().join("soft.png")).unwrap();
    std::fs::hard_link(dir.path().join("scene.toml"), dir.path().join("hard.exr")).unwrap();
    assert_render_refuses(dir.path(), "scene.toml", "soft.png", &[]);
    assert_render_refuses(dir.path(), "scene.toml", "hard.exr", &[]);
}

#[test]
fn view_refuses_a_screenshot_over_its_points_file() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.png"));
    let (ok, _, stderr) = pointray_in(
        dir.path(),
        &["view", "grid.png", "--backend", "cpu", "--frames", "1", "--screenshot", "grid.png"],
    );
    assert!(!ok && stderr.contains("refusing to write over the input file"), "{stderr}");
    #[cfg(unix)]
    {
        std::fs::create_dir(dir.path().join("frames")).unwrap();
        std::fs::hard_link(dir.path().join("grid.png"), dir.path().join("frames/frame-00001.png")).unwrap();
        let args = ["view", "grid.png", "--backend", "cpu", "--frames", "3", "--sequence", "frames"];
        let (ok, _, stderr) = pointray_in(dir.path(), &args);
        assert!(!ok && stderr.contains("refusing to write over the input file"), "{stderr}");
    }
}

#[test]
fn fidelity_refuses_an_image_folder_holding_its_points() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("images")).unwrap();
    write_grid_ply(&dir.path().join("images/view-0-points.png"));
    let before = snapshot(&dir.path().join("images"));
    let args = ["fidelity", "images/view-0-points.png", "mesh.ply", "--images", "images"];
    let (ok, _, stderr) = pointray_in(dir.path(), &args);
    assert!(!ok && stderr.contains("refusing to write over the input file"), "{stderr}");
    assert_eq!(snapshot(&dir.path().join("images")), before, "the image folder changed");
}

#[test]
fn bench_refuses_reports_over_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    for flag in ["--json", "--markdown"] {
        for target in ["scene.toml", "grid.ply"] {
            let (ok, _, stderr) = pointray_in(dir.path(), &["bench", "scene.toml", flag, target]);
            assert!(
                !ok && stderr.contains("refusing to write over the input file"),
                "{flag} {target}: {stderr}"
            );
        }
    }
    let (ok, _, stderr) =
        pointray_in(dir.path(), &["bench", "scene.toml", "--json", "r.json", "--markdown", "r.json"]);
    assert!(!ok && stderr.contains("is also the output"), "one report would replace the other: {stderr}");
}

#[test]
fn bad_output_paths_fail_before_anything_is_loaded() {
    let dir = tempfile::tempdir().unwrap();
    // The points file does not exist: a command that loaded first would report it instead.
    write_points_scene(dir.path(), "scene.toml", "missing.ply");
    for (output, expected) in [
        ("out.jpg", "unsupported image type"),
        ("typo/out.png", "the folder typo does not exist"),
        (".", "unsupported image type"),
        ("out.png/", "ends with a path separator"),
    ] {
        let (ok, _, stderr) = pointray_in(dir.path(), &["render", "scene.toml", "-o", output]);
        assert!(!ok && stderr.contains(expected), "-o {output}: {stderr}");
    }
    std::fs::create_dir(dir.path().join("folder.png")).unwrap();
    let (ok, _, stderr) = pointray_in(dir.path(), &["render", "scene.toml", "-o", "folder.png"]);
    assert!(!ok && stderr.contains("is a folder"), "{stderr}");
    assert!(!dir.path().join(".pointray-cache").exists(), "a failed render leaves no cache folder");
}
