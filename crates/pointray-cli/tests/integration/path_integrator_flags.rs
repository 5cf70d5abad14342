//! `render --integrator path`: the flags reach the renderer (a path-traced image differs from
//! the Whitted one, a seed gives one image), the albedo AOV is written, and a bad integrator
//! name is refused with the names that exist.

use crate::common::{pointray_in, write_grid_ply, write_points_scene};

#[test]
fn the_path_integrator_renders_with_its_seed_and_albedo() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    let render = |output: &str, extra: &[&str]| {
        let mut args =
            vec!["render", "scene.toml", "-o", output, "--backend", "cpu", "--width", "24", "--height", "16"];
        args.extend_from_slice(extra);
        let (ok, _, stderr) = pointray_in(dir.path(), &args);
        assert!(ok, "{output}: {stderr}");
        std::fs::read(dir.path().join(output)).unwrap()
    };
    let path_flags = ["--integrator", "path", "--spp", "4", "--max-depth", "3", "--seed", "5"];
    let path = render("path.png", &path_flags);
    assert_eq!(render("again.png", &path_flags), path, "one seed, one image");
    assert_ne!(render("whitted.png", &[]), path);
    let mut with_aovs = path_flags.to_vec();
    with_aovs.push("--aovs");
    render("aovs.exr", &with_aovs);
    assert!(dir.path().join("aovs.albedo.exr").is_file(), "the albedo AOV is written");
    render("whitted_aovs.exr", &["--aovs"]);
    assert!(!dir.path().join("whitted_aovs.albedo.exr").exists(), "Whitted has no albedo");
}

#[test]
fn an_unknown_integrator_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    let (ok, _, stderr) =
        pointray_in(dir.path(), &["render", "scene.toml", "-o", "x.png", "--integrator", "bdpt"]);
    assert!(!ok);
    assert!(stderr.contains("bdpt") && stderr.contains("whitted") && stderr.contains("path"), "{stderr}");
}
