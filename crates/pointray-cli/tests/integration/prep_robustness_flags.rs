//! `pointray prep --remove-outliers K,N --radius paper|adaptive`: the flags reach prep and
//! bad values are refused with a clear message.

use std::path::Path;
use std::process::{Command, Output};

fn pointray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointray")).args(args).output().expect("pointray runs")
}

/// A 30x30 plane and 5 points far above it.
fn write_plane_with_outliers(path: &Path) {
    let mut positions: Vec<glam::DVec3> =
        (0..900).map(|i| glam::DVec3::new((i % 30) as f64 * 0.1, (i / 30) as f64 * 0.1, 0.0)).collect();
    positions.extend((0..5).map(|i| glam::DVec3::new(0.5 * i as f64, 1.0, 3.0 + i as f64)));
    let cloud = pointray_io::PointCloud::from_positions(positions);
    pointray_io::formats::ply::write_point_cloud(path, &cloud).unwrap();
}

#[test]
fn outliers_are_removed_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    let (input, store) = (dir.path().join("plane.ply"), dir.path().join("plane.patches"));
    write_plane_with_outliers(&input);
    let args = ["prep", input.to_str().unwrap(), "-o", store.to_str().unwrap()];
    let output = pointray(&[&args[..], &["--remove-outliers", "8,2", "--radius", "adaptive"]].concat());
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("5 outliers removed"), "{stdout}");
    assert_eq!(pointray_patches::patch_store::read(&store).unwrap().len(), 900);
}

#[test]
fn bad_filter_values_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (input, store) = (dir.path().join("plane.ply"), dir.path().join("plane.patches"));
    write_plane_with_outliers(&input);
    for bad in ["0,2", "8", "8,-1", "x,2", "8,nan"] {
        let output = pointray(&[
            "prep",
            input.to_str().unwrap(),
            "-o",
            store.to_str().unwrap(),
            "--remove-outliers",
            bad,
        ]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "`{bad}` must be refused");
        assert!(stderr.contains("--remove-outliers") && !stderr.contains("panicked"), "`{bad}`: {stderr}");
        assert!(!store.exists());
    }
}
