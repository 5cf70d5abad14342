//! Geo-referenced scenes (UTM coordinates: 10^5 to 10^7 from the origin) render as the same
//! scene at the origin does: the loader recentres camera, lights and objects in f64 before
//! anything goes to f32, for every backend. A scene scaled far from the usual sizes renders
//! as at its own scale, with the path integrator's point lights falling off over the file's
//! distances.

use std::path::Path;

use glam::DVec3;
use pointray_io::PointCloud;
use pointray_scene::{Integrator, LoadOptions, LoadedScene, RenderSettings, RenderedImage, load_scene};

/// A UTM-sized position (easting, northing, height).
const UTM: DVec3 = DVec3::new(640_000.0, 5_000_000.0, 100.0);

fn wavy_grid(offset: DVec3) -> PointCloud {
    let positions = (0..900)
        .map(|i| {
            let (x, z) = (f64::from(i % 30) * 0.1, f64::from(i / 30) * 0.1);
            offset + DVec3::new(x, 0.15 * (2.0 * x).sin() * (1.5 * z).cos(), z)
        })
        .collect();
    PointCloud::from_positions(positions)
}

/// A scene of `points` at `translate`, seen by a camera and lit by a light placed relative to
/// `space` (the coordinates the scene lives in).
fn write_scene(dir: &Path, name: &str, points: &str, translate: DVec3, space: DVec3) -> std::path::PathBuf {
    let at = |p: DVec3| format!("[{}, {}, {}]", space.x + p.x, space.y + p.y, space.z + p.z);
    let text = format!(
        "[camera]\nposition = {}\nlook_at = {}\n\n[[lights]]\ntype = \"point\"\nposition = {}\n\n\
         [[objects]]\ntype = \"points\"\npath = \"{points}\"\n[objects.transform]\ntranslate = [{}, {}, {}]\n\n\
         [[objects]]\ntype = \"ground\"\nauto = true\n[objects.material]\nreflectivity = 0.3\n",
        at(DVec3::new(1.45, 2.1, 5.2)),
        at(DVec3::new(1.45, 0.0, 1.45)),
        at(DVec3::new(0.5, 4.0, 2.5)),
        translate.x,
        translate.y,
        translate.z,
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Rendered as `pointray render` does: depths in the file's units.
fn render(scene: &Path) -> RenderedImage {
    let loaded = load_scene(scene, &LoadOptions::default()).expect("the scene loads");
    let settings = RenderSettings { width: 96, height: 72, ..loaded.settings };
    render_with(&loaded, &settings)
}

fn render_with(loaded: &LoadedScene, settings: &RenderSettings) -> RenderedImage {
    let mut image = pointray_cpu::render(&loaded.scene, settings);
    image.scale_depth(loaded.space.scale as f32);
    image
}

/// The mean colour difference and the share of pixels whose hit object differs.
fn difference(a: &RenderedImage, b: &RenderedImage) -> (f32, f32) {
    let n = a.pixel_count() as f32;
    let colour = a.color.iter().zip(&b.color).map(|(x, y)| (*x - *y).abs().max_element()).sum::<f32>() / n;
    let hits = a.instance_id.iter().zip(&b.instance_id).filter(|(x, y)| x != y).count() as f32 / n;
    (colour, hits)
}

#[test]
fn utm_scenes_render_as_the_same_scene_at_the_origin() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, offset| {
        pointray_io::formats::ply::write_point_cloud(&dir.path().join(name), &wavy_grid(offset)).unwrap()
    };
    write("local.ply", DVec3::ZERO);
    write("utm.ply", UTM);
    let reference = render(&write_scene(dir.path(), "origin.toml", "local.ply", DVec3::ZERO, DVec3::ZERO));
    let model = reference.instance_id.iter().filter(|&&id| id == 0).count();
    assert!(model > reference.pixel_count() / 10, "the model fills part of the reference image");
    let geo_points = render(&write_scene(dir.path(), "points.toml", "utm.ply", DVec3::ZERO, UTM));
    let geo_translate = render(&write_scene(dir.path(), "moved.toml", "local.ply", UTM, UTM));
    for (what, image) in [("UTM points", geo_points), ("a UTM translation", geo_translate)] {
        let (colour, hits) = difference(&reference, &image);
        assert!(hits < 0.01, "{what}: {:.1}% of pixels hit another object", 100.0 * hits);
        assert!(colour < 0.01, "{what}: colours differ by {colour} on average");
    }
}

#[test]
fn a_cloud_scaled_by_1e10_renders_as_at_its_own_scale() {
    let dir = tempfile::tempdir().unwrap();
    pointray_io::formats::ply::write_point_cloud(&dir.path().join("local.ply"), &wavy_grid(DVec3::ZERO))
        .unwrap();
    let scene = |scale: &str| {
        let path = dir.path().join(format!("scaled-{scale}.toml"));
        let text = format!(
            "[[lights]]\ntype = \"directional\"\ndirection = [-0.4, -1.0, -0.5]\n\n\
             [[objects]]\ntype = \"points\"\npath = \"local.ply\"\n[objects.transform]\nscale = {scale}\n\n\
             [[objects]]\ntype = \"ground\"\nauto = true\n"
        );
        std::fs::write(&path, text).unwrap();
        render(&path)
    };
    let (unit, scaled) = (scene("1.0"), scene("1e10"));
    let (colour, hits) = difference(&unit, &scaled);
    assert!(hits < 0.01, "{:.1}% of pixels hit another object", 100.0 * hits);
    assert!(colour < 0.01, "colours differ by {colour} on average");
    let hit = (0..unit.pixel_count()).find(|&i| unit.depth[i].is_finite()).expect("something is hit");
    let ratio = scaled.depth[hit] / unit.depth[hit];
    assert!((ratio / 1e10 - 1.0).abs() < 1e-3, "depths are in the file's units: ratio {ratio}");
}

#[test]
fn a_path_traced_point_light_lights_a_rescaled_scene_as_at_its_own_scale() {
    let dir = tempfile::tempdir().unwrap();
    pointray_io::formats::ply::write_point_cloud(&dir.path().join("local.ply"), &wavy_grid(DVec3::ZERO))
        .unwrap();
    // 2^24 takes the scene far beyond the usual sizes, so it renders rescaled; a point light
    // 2^24 times farther needs 2^48 times the intensity to light it as before.
    let scene = |name: &str, factor: f64| {
        let at = |p: DVec3| format!("[{}, {}, {}]", factor * p.x, factor * p.y, factor * p.z);
        let text = format!(
            "background = [0.0, 0.0, 0.0]\n[camera]\nposition = {}\nlook_at = {}\n\n\
             [[lights]]\ntype = \"point\"\nposition = {}\nintensity = {}\n\n\
             [[objects]]\ntype = \"points\"\npath = \"local.ply\"\n[objects.transform]\nscale = {factor}\n",
            at(DVec3::new(1.45, 2.1, 5.2)),
            at(DVec3::new(1.45, 0.0, 1.45)),
            at(DVec3::new(0.5, 4.0, 2.5)),
            16.0 * factor * factor,
        );
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let loaded = load_scene(&path, &LoadOptions::default()).expect("the scene loads");
        let settings = RenderSettings {
            width: 48,
            height: 36,
            integrator: Integrator::Path,
            samples_per_pixel: 4,
            max_depth: 2,
            ..loaded.settings
        };
        (render_with(&loaded, &settings), loaded.space.scale)
    };
    let ((unit, unit_scale), (scaled, scaled_scale)) =
        (scene("unit.toml", 1.0), scene("scaled.toml", 2f64.powi(24)));
    assert_eq!(unit_scale, 1.0);
    assert!(scaled_scale > 1e6, "the scaled scene renders rescaled, by {scaled_scale}");
    let lit = unit.color.iter().filter(|c| c.max_element() > 0.05).count();
    assert!(lit > unit.pixel_count() / 10, "the light lights the model: {lit} pixels");
    let (colour, hits) = difference(&unit, &scaled);
    assert!(hits < 0.01, "{:.1}% of pixels hit another object", 100.0 * hits);
    assert!(colour < 0.02, "colours differ by {colour} on average");
}
