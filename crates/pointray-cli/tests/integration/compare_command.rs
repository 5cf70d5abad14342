//! `compare`: a path-traced render against a reference of more samples converges as the
//! samples grow, an image against itself has no error, and images that cannot be compared
//! are refused with their files named.

use crate::common::{pointray_in, write_grid_ply, write_points_scene};

/// The RMSE that `compare` prints.
fn rmse(stdout: &str) -> f64 {
    let after = stdout.split("RMSE ").nth(1).unwrap_or_else(|| panic!("no RMSE in {stdout}"));
    after.split(',').next().unwrap().trim().parse().unwrap()
}

#[test]
fn more_samples_come_closer_to_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    let render = |output: &str, spp: &str, seed: &str| {
        let args = [
            "render",
            "scene.toml",
            "-o",
            output,
            "--backend",
            "cpu",
            "--width",
            "24",
            "--height",
            "16",
            "--integrator",
            "path",
            "--max-depth",
            "3",
            "--spp",
            spp,
            "--seed",
            seed,
        ];
        let (ok, _, stderr) = pointray_in(dir.path(), &args);
        assert!(ok, "{output}: {stderr}");
    };
    render("reference.exr", "256", "1");
    render("few.exr", "2", "2");
    render("more.exr", "32", "2");
    let compare = |image: &str| {
        let (ok, stdout, stderr) = pointray_in(dir.path(), &["compare", image, "reference.exr"]);
        assert!(ok, "{stderr}");
        stdout
    };
    let (few, more) = (rmse(&compare("few.exr")), rmse(&compare("more.exr")));
    assert!(more < 0.5 * few, "32 samples {more} against 2 samples {few}");
    let itself = compare("reference.exr");
    assert_eq!(rmse(&itself), 0.0);
    assert!(itself.contains("PSNR inf dB") && itself.contains("energy 1.0000"), "{itself}");
}

#[test]
fn images_that_cannot_be_compared_are_refused_with_their_names() {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    for (output, width) in [("wide.exr", "24"), ("narrow.exr", "20"), ("shown.png", "20")] {
        let args =
            ["render", "scene.toml", "-o", output, "--backend", "cpu", "--width", width, "--height", "8"];
        assert!(pointray_in(dir.path(), &args).0);
    }
    let refused = |args: &[&str], needles: &[&str]| {
        let (ok, _, stderr) = pointray_in(dir.path(), args);
        assert!(!ok, "{args:?} was accepted");
        assert!(needles.iter().all(|n| stderr.contains(n)), "{args:?}: {stderr}");
    };
    refused(&["compare", "wide.exr", "narrow.exr"], &["wide.exr", "narrow.exr", "24x8", "20x8"]);
    refused(&["compare", "shown.png", "narrow.exr"], &["shown.png", ".exr"]);
    refused(&["compare", "missing.exr", "narrow.exr"], &["missing.exr"]);
}
