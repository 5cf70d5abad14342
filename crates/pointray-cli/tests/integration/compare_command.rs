//! `compare`: a path-traced render against a reference of more samples converges as the
//! samples grow (and `render --denoise` brings a preview closer), an image against itself has
//! no error, and images that cannot be compared are refused with their files named.

use std::path::Path;

use crate::common::{pointray_in, write_grid_ply, write_points_scene};

/// A folder holding the grid scene.
fn grid_scene() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write_grid_ply(&dir.path().join("grid.ply"));
    write_points_scene(dir.path(), "scene.toml", "grid.ply");
    dir
}

/// Path traces the grid scene at `size` (width, height) to `output`; returns what it printed.
fn path_render(dir: &Path, output: &str, size: [&str; 2], spp: &str, seed: &str, extra: &[&str]) -> String {
    let mut args = vec!["render", "scene.toml", "-o", output, "--backend", "cpu", "--width", size[0]];
    args.extend([
        "--height",
        size[1],
        "--integrator",
        "path",
        "--max-depth",
        "3",
        "--spp",
        spp,
        "--seed",
        seed,
    ]);
    args.extend_from_slice(extra);
    let (ok, stdout, stderr) = pointray_in(dir, &args);
    assert!(ok, "{output}: {stderr}");
    stdout
}

/// What `compare IMAGE reference.exr` prints, and the RMSE in it.
fn compare_with_reference(dir: &Path, image: &str) -> (String, f64) {
    let (ok, stdout, stderr) = pointray_in(dir, &["compare", image, "reference.exr"]);
    assert!(ok, "{stderr}");
    let after = stdout.split("RMSE ").nth(1).unwrap_or_else(|| panic!("no RMSE in {stdout}"));
    let rmse = after.split(',').next().unwrap().trim().parse().unwrap();
    (stdout, rmse)
}

#[test]
fn more_samples_come_closer_to_the_reference() {
    let dir = grid_scene();
    let size = ["24", "16"];
    path_render(dir.path(), "reference.exr", size, "256", "1", &[]);
    path_render(dir.path(), "few.exr", size, "2", "2", &[]);
    path_render(dir.path(), "more.exr", size, "32", "2", &[]);
    let (few, more) =
        (compare_with_reference(dir.path(), "few.exr").1, compare_with_reference(dir.path(), "more.exr").1);
    assert!(more < 0.5 * few, "32 samples {more} against 2 samples {few}");
    let (itself, rmse) = compare_with_reference(dir.path(), "reference.exr");
    assert_eq!(rmse, 0.0);
    assert!(itself.contains("PSNR inf dB") && itself.contains("energy 1.0000"), "{itself}");
}

#[test]
fn a_denoised_preview_comes_closer_to_the_reference_than_the_noisy_one() {
    let dir = grid_scene();
    let size = ["48", "32"];
    path_render(dir.path(), "reference.exr", size, "512", "3", &[]);
    path_render(dir.path(), "noisy.exr", size, "2", "3", &[]);
    let printed = path_render(dir.path(), "denoised.exr", size, "2", "3", &["--denoise"]);
    assert!(printed.contains("denoised in"), "{printed}");
    let noisy = compare_with_reference(dir.path(), "noisy.exr").1;
    let denoised = compare_with_reference(dir.path(), "denoised.exr").1;
    assert!(denoised < 0.6 * noisy, "denoised {denoised} against noisy {noisy}");
}

#[test]
fn images_that_cannot_be_compared_are_refused_with_their_names() {
    let dir = grid_scene();
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

/// A 100-byte Radiance file whose header claims 16384 x 1e9 texels is refused before decoding,
/// naming the file, where the decoder's allocation used to abort the process.
#[test]
fn an_image_header_claiming_more_than_memory_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1000000000 +X 16384\n";
    std::fs::write(dir.path().join("huge.hdr"), [&header[..], &[0x80; 16]].concat()).unwrap();
    let (ok, _, stderr) = pointray_in(dir.path(), &["compare", "huge.hdr", "huge.hdr"]);
    assert!(!ok && stderr.contains("huge.hdr") && stderr.contains("16384 x 1000000000"), "{stderr}");
    assert!(stderr.contains("of memory") && !stderr.contains("panicked"), "{stderr}");
}
