//! The procedural demo scene renders with no data file.

use pointray_scene::demo_scene;
use pointray_test_support::floor_scenes::settings;
use pointray_test_support::{assert_no_validation_messages, vulkan_renderer};

#[test]
fn the_procedural_demo_renders() {
    let Some(renderer) = vulkan_renderer() else { return };
    let scene = demo_scene().expect("the demo scene builds");
    let image = renderer.render(&scene, &settings(128)).expect("the demo renders");
    assert!(
        image.color.iter().all(|c| c.is_finite() && c.min_element() >= 0.0),
        "colours must be finite and non-negative"
    );
    for index in 0..scene.objects.len() as u32 {
        let pixels = image.instance_id.iter().filter(|&&id| id == index).count();
        assert!(
            pixels > 20,
            "object {index} ({}) covers only {pixels} pixels",
            scene.objects[index as usize].name
        );
    }
    assert_no_validation_messages(&renderer);
}
