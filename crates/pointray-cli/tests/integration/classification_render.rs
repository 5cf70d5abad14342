//! `color_source = "classification"` and `"height"` reach the image: the CPU renderer shows
//! the colours computed at load with no change of its own.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use pointray_scene::classification_palette::classification_color;
use pointray_scene::{LoadOptions, RenderSettings, load_scene};

/// A 50x50 plane in z = 0 over [-1, 1]², ground (2) left of x = 0, buildings (6) right of it.
fn write_plane(dir: &Path) -> PathBuf {
    let positions: Vec<DVec3> = (0..2500)
        .map(|i| DVec3::new(-1.0 + 0.04 * (i % 50) as f64, -1.0 + 0.04 * (i / 50) as f64, 0.0))
        .collect();
    let classifications = Some(positions.iter().map(|p| if p.x < 0.0 { 2 } else { 6 }).collect());
    let cloud = pointray_io::PointCloud { positions, classifications, ..Default::default() };
    let path = dir.join("classes.ply");
    pointray_io::formats::ply::write_point_cloud(&path, &cloud).unwrap();
    path
}

/// The plane seen head-on, lit from the camera, with no ambient or specular light: a pixel
/// shows its point colour as it is.
fn write_scene(dir: &Path, points: &Path, color_source: &str) -> PathBuf {
    let text = format!(
        "background = [0.0, 0.0, 0.0]\n[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         vfov_degrees = 30.0\n[[lights]]\ntype = \"directional\"\ndirection = [0.0, 0.0, -1.0]\n\
         [[objects]]\ntype = \"points\"\npath = \"{}\"\n[objects.material]\nambient = 0.0\n\
         specular = 0.0\ncolor_source = \"{color_source}\"\n",
        points.display()
    );
    let path = dir.join(format!("{color_source}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn srgb_to_linear(srgb: [u8; 3]) -> Vec3 {
    Vec3::from(srgb.map(|c| {
        let c = f32::from(c) / 255.0;
        if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
    }))
}

fn render(scene: &Path) -> pointray_scene::RenderedImage {
    let loaded = load_scene(scene, &LoadOptions::default()).unwrap();
    pointray_cpu::render(&loaded.scene, &RenderSettings { width: 60, height: 60, ..loaded.settings })
}

#[test]
fn ground_and_buildings_show_in_their_asprs_colours() {
    let dir = tempfile::tempdir().unwrap();
    let image = render(&write_scene(dir.path(), &write_plane(dir.path()), "classification"));
    let (ground, building) =
        (srgb_to_linear(classification_color(2)), srgb_to_linear(classification_color(6)));
    // Columns 12 and 48 look at x = -0.48 and 0.48, well inside each half.
    for row in [15, 30, 45] {
        let (left, right) = (image.color[row * 60 + 12], image.color[row * 60 + 48]);
        assert!((left - ground).length() < 0.01, "row {row}: {left} is not ground {ground}");
        assert!((right - building).length() < 0.01, "row {row}: {right} is not building {building}");
    }
}

#[test]
fn height_colours_the_plane_from_bottom_to_top() {
    let dir = tempfile::tempdir().unwrap();
    // The plane stands upright in the world (z = 0 faces the camera): world Y is the file's y.
    let image = render(&write_scene(dir.path(), &write_plane(dir.path()), "height"));
    let viridis = pointray_scene::color_ramp::ColorRamp::named("viridis").unwrap();
    let half_height = 3.0 * 15f32.to_radians().tan();
    for row in [8, 20, 30, 40, 51] {
        // The plane's y at the pixel's centre, as a fraction of the way from y = -1 to 0.96.
        let y = half_height * (1.0 - 2.0 * (row as f32 + 0.5) / 60.0);
        let expected = viridis.color_at((y + 1.0) / 1.96);
        let seen = image.color[row * 60 + 30];
        assert!((seen - expected).length() < 0.05, "row {row} (y = {y}): {seen}, expected {expected}");
    }
}
