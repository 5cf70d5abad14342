//! Shader execution reordering changes the order of work, never the picture. On a device
//! without it (lavapipe), asking for it is a clear error instead.

use crate::common;

use common::{assert_no_validation_messages, renderer, sphere_on_floor};
use pointray_scene::RenderSettings;
use pointray_vulkan::{DeviceOptions, DeviceSelector, VulkanError, VulkanRenderer};

#[test]
fn hit_reordering_draws_the_same_picture_or_is_refused() {
    let Some(plain) = renderer() else { return };
    let reordering = VulkanRenderer::with_hit_reordering(DeviceSelector::Auto, DeviceOptions::VALIDATED);
    if !plain.device_info().hit_reordering {
        let Err(VulkanError::InvalidSettings(message)) = reordering else {
            panic!("a device without hit reordering must refuse it");
        };
        assert!(message.contains("VK_NV_ray_tracing_invocation_reorder"), "{message}");
        return;
    }
    let reordering = reordering.expect("the device offers hit reordering");
    let scene = sphere_on_floor(0.5, 1.0);
    let settings = RenderSettings { width: 96, height: 64, ..RenderSettings::default() };
    let expected = plain.render(&scene, &settings).expect("renders");
    let reordered = reordering.render(&scene, &settings).expect("renders with reordering");
    assert_eq!(reordered, expected, "reordering changed the picture");
    assert_no_validation_messages(&plain);
    assert_no_validation_messages(&reordering);
}
