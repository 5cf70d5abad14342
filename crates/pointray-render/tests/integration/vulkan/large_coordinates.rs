//! A geo-referenced scene renders on the GPU as the same scene at the origin: the loader's
//! f64 recentring reaches this backend too.

use std::path::Path;

use glam::DVec3;
use pointray_scene::demo::DEMO_SCENE_TOML;
use pointray_scene::object_spec::ShapeSpec;
use pointray_scene::scene_file::LightSpec;
use pointray_scene::{LoadOptions, SceneFile, load_scene_file};
use pointray_test_support::floor_scenes::{iou, settings};
use pointray_test_support::{assert_no_validation_messages, vulkan_renderer};

/// A UTM-sized position (easting, northing, height).
const UTM: [f64; 3] = [640_000.0, 5_000_000.0, 100.0];

/// The demo scene with everything it places moved by `UTM`.
fn moved_demo() -> SceneFile {
    let mut file = SceneFile::parse(DEMO_SCENE_TOML, Path::new("demo.toml")).unwrap();
    let shift = |p: &mut [f64; 3]| *p = (DVec3::from(*p) + DVec3::from(UTM)).to_array();
    let camera = file.camera.as_mut().expect("the demo has a camera");
    shift(&mut camera.position);
    shift(&mut camera.look_at);
    for light in &mut file.lights {
        if let LightSpec::Point { position, .. } = light {
            shift(position);
        }
    }
    for object in file.objects.iter_mut().filter(|o| !matches!(o.shape, ShapeSpec::Ground { .. })) {
        shift(object.transform.translate.get_or_insert([0.0; 3]));
    }
    file
}

#[test]
fn a_utm_scene_renders_as_at_the_origin() {
    let Some(renderer) = vulkan_renderer() else { return };
    let at_origin = SceneFile::parse(DEMO_SCENE_TOML, Path::new("demo.toml")).unwrap();
    let [reference, moved] = [at_origin, moved_demo()].map(|file| {
        let scene = load_scene_file(&file, &LoadOptions::default()).expect("the scene loads").scene;
        renderer.render(&scene, &settings(96)).expect("the scene renders")
    });
    let hits = |frame: &pointray_scene::RenderedImage| {
        frame.instance_id.iter().map(|&id| id == 1).collect::<Vec<_>>()
    };
    let overlap = iou(&hits(&reference), &hits(&moved));
    assert!(overlap > 0.98, "the sphere's pixels overlap by {overlap}");
    let n = reference.pixel_count() as f32;
    let colour =
        reference.color.iter().zip(&moved.color).map(|(a, b)| (*a - *b).abs().max_element()).sum::<f32>() / n;
    assert!(colour < 0.01, "colours differ by {colour} on average");
    assert_no_validation_messages(&renderer);
}
