//! `scenes/autzen.toml`, the real airborne LiDAR tile, renders to a sensible image
//! on the CPU backend: no NaN or infinite pixel, the tile fills a plausible part of the image,
//! it casts shadows, and its own RGB comes through.

use std::path::{Path, PathBuf};

use pointray_test_support::data_file;

use glam::Vec3;
use pointray_scene::object_spec::ShapeSpec;
use pointray_scene::{LoadOptions, RenderSettings, RenderedImage, SceneFile, load_scene_file};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
/// The tile is the scene's first object.
const TILE: u32 = 0;

/// The shipped scene, with its points path pointed at the data folder in use.
fn autzen_scene(data: PathBuf) -> SceneFile {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/autzen.toml");
    let mut file = SceneFile::read(&scene).expect("scenes/autzen.toml parses");
    match &mut file.objects[TILE as usize].shape {
        ShapeSpec::Points { path, .. } => *path = data,
        other => panic!("the first object of autzen.toml should be the tile, not {}", other.type_name()),
    }
    file
}

fn luminance(color: Vec3) -> f32 {
    color.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

fn tile_pixels(image: &RenderedImage) -> Vec<usize> {
    (0..image.pixel_count()).filter(|&i| image.instance_id[i] == TILE).collect()
}

#[test]
fn autzen_renders_lit_shadowed_and_in_colour() {
    let data = data_file("scans/autzen_trim.las");
    let loaded =
        load_scene_file(&autzen_scene(data), &LoadOptions::default()).expect("the autzen scene loads");
    let settings = RenderSettings { width: WIDTH, height: HEIGHT, ..loaded.settings };
    let image = pointray_cpu::render(&loaded.scene, &settings);
    let unshadowed = pointray_cpu::render(&loaded.scene, &RenderSettings { shadows: false, ..settings });

    let bad = image.color.iter().filter(|c| !c.is_finite()).count();
    assert_eq!(bad, 0, "{bad} pixels are NaN or infinite");

    let tile = tile_pixels(&image);
    let coverage = tile.len() as f32 / image.pixel_count() as f32;
    assert!((0.05..0.9).contains(&coverage), "the tile covers {:.1}% of the image", 100.0 * coverage);

    // Shadows: tile pixels that the light reaches without shadow rays but not with them.
    let shadowed =
        tile.iter().filter(|&&i| luminance(image.color[i]) < 0.7 * luminance(unshadowed.color[i])).count();
    let shadowed_share = shadowed as f32 / tile.len() as f32;
    assert!(shadowed_share > 0.01, "only {:.2}% of the tile is in shadow", 100.0 * shadowed_share);
    let mut lit: Vec<f32> = tile.iter().map(|&i| luminance(image.color[i])).collect();
    lit.sort_by(f32::total_cmp);
    let median = lit[lit.len() / 2];
    let darker = tile.iter().filter(|&&i| luminance(image.color[i]) < 0.5 * median).count();
    assert!(darker > 0, "no tile pixel is darker than half the median ({median})");

    // Colour: the chromaticity of the tile varies (grass, roofs, roads), so the file's RGB
    // reached the image rather than one material colour.
    let chroma: Vec<Vec3> = tile
        .iter()
        .map(|&i| image.color[i])
        .filter(|c| c.element_sum() > 0.01)
        .map(|c| c / c.element_sum())
        .collect();
    let mean = chroma.iter().copied().sum::<Vec3>() / chroma.len() as f32;
    let spread =
        (chroma.iter().map(|c| (*c - mean).length_squared()).sum::<f32>() / chroma.len() as f32).sqrt();
    eprintln!(
        "autzen {WIDTH}x{HEIGHT}: tile {:.1}%, shadowed {:.1}%, {darker} below half the median, chroma spread {spread:.4}",
        100.0 * coverage,
        100.0 * shadowed_share
    );
    assert!(spread > 0.02, "the tile's colours barely vary (chromaticity spread {spread})");
}
