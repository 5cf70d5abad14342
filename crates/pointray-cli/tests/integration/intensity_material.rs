//! `color_source = "intensity"`: the ramp's colours replace the points' colours at load, the
//! CPU renderer shows them with no change of its own, and a cloud without intensities or a
//! contradictory material is refused with a message naming the file.

use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_scene::{Geometry, LoadOptions, RenderSettings, load_scene};

/// A 50x50 plane in z = 0 over [-1, 1]², its intensity rising from 0 at x = -1 to 1 at x = 1.
fn write_plane(dir: &Path, with_intensity: bool) -> PathBuf {
    let positions: Vec<DVec3> = (0..2500)
        .map(|i| DVec3::new(-1.0 + 0.04 * (i % 50) as f64, -1.0 + 0.04 * (i / 50) as f64, 0.0))
        .collect();
    let intensities = with_intensity.then(|| positions.iter().map(|p| ((p.x + 1.0) * 0.5) as f32).collect());
    let cloud = pointray_io::PointCloud { positions, intensities, ..Default::default() };
    let path = dir.join(if with_intensity { "lit.ply" } else { "plain.ply" });
    pointray_io::formats::ply::write_point_cloud(&path, &cloud).unwrap();
    path
}

/// A scene of `points` seen head-on, lit from the camera, with `material` (TOML lines).
fn write_scene(dir: &Path, points: &Path, material: &str) -> PathBuf {
    let text = format!(
        r#"
background = [0.0, 0.0, 0.0]
[camera]
position = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
vfov_degrees = 30.0
[[lights]]
type = "directional"
direction = [0.0, 0.0, -1.0]
[[objects]]
type = "points"
path = "{}"
[objects.material]
ambient = 0.0
specular = 0.0
{material}
"#,
        points.display()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_grey_ramp_turns_intensity_into_colour_in_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(
        dir.path(),
        &write_plane(dir.path(), true),
        "color_source = \"intensity\"\nramp = \"grey\"",
    );
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let object = &loaded.scene.objects[0];
    assert!(object.material.use_point_colors, "the renderers read the ramp's colours as point colours");
    let Geometry::Patches(patches) = &object.geometry else { panic!("a point set") };
    for record in &patches.cold {
        let expected = (record.intensity * 255.0).round();
        assert!(
            (record.color().x * 255.0 - expected).abs() < 0.51,
            "intensity {} became {}",
            record.intensity,
            record.color()
        );
    }

    // Head-on, lit from the camera, no ambient or specular: a pixel's red is the ramp's grey,
    // which is the intensity (x + 1) / 2 of the plane point it sees, give or take the
    // patch's reach (the hit may take the colour of a point up to d_i = 0.08 away).
    let settings = RenderSettings { width: 60, height: 60, ..loaded.settings };
    let frame = pointray_cpu::render(&loaded.scene, &settings);
    let half_width = 3.0 * 15f32.to_radians().tan();
    for column in (3..60).step_by(6) {
        let x = half_width * (2.0 * (column as f32 + 0.5) / 60.0 - 1.0);
        let red = frame.color[30 * 60 + column].x;
        assert!((red - (x + 1.0) * 0.5).abs() < 0.05, "column {column} (x = {x}): red {red}");
    }
}

#[test]
fn colour_stops_and_a_range_are_applied() {
    let dir = tempfile::tempdir().unwrap();
    let material = "color_source = \"intensity\"\nramp = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]\nintensity_range = [0.25, 0.75]";
    let scene = write_scene(dir.path(), &write_plane(dir.path(), true), material);
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    let Geometry::Patches(patches) = &loaded.scene.objects[0].geometry else { panic!("a point set") };
    for record in &patches.cold {
        let color = record.color();
        match record.intensity {
            i if i <= 0.25 => assert_eq!(color, glam::Vec3::X, "below the range: the first stop"),
            i if i >= 0.75 => assert_eq!(color, glam::Vec3::Z, "above the range: the last stop"),
            i => assert!((color.z - (i - 0.25) * 2.0).abs() < 0.01, "{i} became {color}"),
        }
    }
}

#[test]
fn a_cloud_without_intensity_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let points = write_plane(dir.path(), false);
    let scene = write_scene(dir.path(), &points, "color_source = \"intensity\"");
    let error = load_scene(&scene, &LoadOptions::default()).unwrap_err().to_string();
    assert!(error.contains("plain.ply") && error.contains("no intensity"), "{error}");
    assert!(error.contains("color_source"), "{error}");
}

#[test]
fn contradictory_or_unknown_colour_settings_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let points = write_plane(dir.path(), true);
    let cases = [
        ("color_source = \"points\"\nuse_point_colors = true", "not both"),
        ("color_source = \"intensity\"\nramp = \"jet\"", "unknown ramp `jet`"),
        ("color_source = \"fixed\"\nramp = \"grey\"", "applies only with"),
        ("color_source = \"intensity\"\nramp = [[1.0, 0.0, 0.0]]", "at least 2"),
        ("color_source = \"paint\"", "unknown variant"),
    ];
    for (material, expected) in cases {
        let scene = write_scene(dir.path(), &points, material);
        let error = load_scene(&scene, &LoadOptions::default()).unwrap_err().to_string();
        assert!(error.contains(expected) && error.contains("scene.toml"), "{material}: {error}");
    }
}

#[test]
fn use_point_colors_still_means_points() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), &write_plane(dir.path(), true), "use_point_colors = true");
    let loaded = load_scene(&scene, &LoadOptions::default()).unwrap();
    assert!(loaded.scene.objects[0].material.use_point_colors);
}
