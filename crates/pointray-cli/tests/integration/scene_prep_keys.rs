//! A points object's `prep` table in a scene file reaches prep: the same settings, by the same
//! names, as `pointray prep`'s flags.

use std::path::{Path, PathBuf};

use pointray_scene::{Geometry, LoadOptions, load_scene};

/// A 30x30 plane and 5 points far above it.
fn write_plane_with_outliers(dir: &Path) -> PathBuf {
    let mut positions: Vec<glam::DVec3> =
        (0..900).map(|i| glam::DVec3::new((i % 30) as f64 * 0.1, (i / 30) as f64 * 0.1, 0.0)).collect();
    positions.extend((0..5).map(|i| glam::DVec3::new(0.5 * i as f64, 1.0, 3.0 + i as f64)));
    let path = dir.join("plane.ply");
    pointray_io::formats::ply::write_point_cloud(&path, &pointray_io::PointCloud::from_positions(positions))
        .unwrap();
    path
}

/// A scene of the plane with `keys` as its `prep` table (none when empty).
fn write_scene(dir: &Path, keys: &str) -> PathBuf {
    let points = write_plane_with_outliers(dir);
    let path = dir.join("scene.toml");
    let prep = if keys.is_empty() { String::new() } else { format!("[objects.prep]\n{keys}\n") };
    std::fs::write(&path, format!("[[objects]]\ntype = \"points\"\npath = \"{}\"\n{prep}", points.display()))
        .unwrap();
    path
}

fn patch_radii(scene: &Path) -> Vec<f32> {
    let loaded = load_scene(scene, &LoadOptions::default()).unwrap();
    let Geometry::Patches(patches) = &loaded.scene.objects[0].geometry else { panic!("a point set") };
    patches.hot.iter().map(|hot| hot.radius()).collect()
}

#[test]
fn outliers_are_removed_and_the_radius_mode_applies() {
    let dir = tempfile::tempdir().unwrap();
    let default = patch_radii(&write_scene(dir.path(), ""));
    assert_eq!(default.len(), 905);
    let filtered = patch_radii(&write_scene(dir.path(), "remove_outliers = { neighbors = 8, sigmas = 2.0 }"));
    assert_eq!(filtered.len(), 900);
    assert_eq!(patch_radii(&write_scene(dir.path(), "radius = \"cell\"")), default, "cell is the default");
    let paper = patch_radii(&write_scene(dir.path(), "radius = \"paper\""));
    // On the grid (spacing 0.1) the paper's disks reach a diagonal neighbour two rows away;
    // the cell radius only 1.5 times the cell's half-diagonal.
    assert!(paper.iter().zip(&default).all(|(p, c)| c <= p), "a cell radius past the paper's");
    assert!((default[450] - 1.5 * 0.05 * 2f32.sqrt()).abs() < 1e-4, "{}", default[450]);
    let adaptive = patch_radii(&write_scene(dir.path(), "radius = \"adaptive\""));
    assert_eq!(adaptive.len(), 905);
    assert!(adaptive.iter().zip(&paper).any(|(a, p)| a != p), "`radius = \"adaptive\"` changed no radius");
    let halved = patch_radii(&write_scene(dir.path(), "disk_scale = 0.5"));
    assert!(halved.iter().zip(&default).all(|(h, c)| (h - 0.5 * c).abs() <= 1e-6 * c), "disk_scale");
}

#[test]
fn bad_keys_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    for (keys, expected) in [
        ("remove_outliers = { neighbors = 0, sigmas = 2.0 }", "remove_outliers.neighbors"),
        ("remove_outliers = { neighbors = 8, sigmas = -1.0 }", "remove_outliers.sigmas"),
        ("remove_outliers = { neighbors = 8 }", "sigmas"),
        ("radius = \"huge\"", "unknown variant"),
        ("disk-scale = 0.5", "unknown field"),
        ("k = 2", "prep.k"),
    ] {
        let error =
            load_scene(&write_scene(dir.path(), keys), &LoadOptions::default()).unwrap_err().to_string();
        assert!(error.contains(expected) && error.contains("scene.toml"), "{keys}: {error}");
    }
}
