//! Reflectivity 0 renders as max_depth 1; reflectivity 0.5 changes the floor under the model.

use crate::common;

use common::{assert_no_validation_messages, renderer, settings, sphere_on_floor};
use pointray_scene::RenderSettings;

const FLOOR: u32 = 1;

#[test]
fn reflectivity_zero_equals_depth_one_and_half_changes_the_floor() {
    let Some(renderer) = renderer() else { return };
    let depth_two = RenderSettings { max_depth: 2, ..settings(128) };
    let depth_one = RenderSettings { max_depth: 1, ..depth_two };

    let matte = renderer.prepare(&sphere_on_floor(0.0, 1.0)).expect("prepares");
    let matte_two = renderer.trace(&matte, &depth_two).expect("traces");
    let matte_one = renderer.trace(&matte, &depth_one).expect("traces");
    let largest = matte_two
        .color
        .iter()
        .zip(&matte_one.color)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0, f32::max);
    assert!(largest < 1e-6, "reflectivity 0 at depth 2 differs from depth 1 by {largest}");

    let mirror = renderer.prepare(&sphere_on_floor(0.5, 1.0)).expect("prepares");
    let mirror_two = renderer.trace(&mirror, &depth_two).expect("traces");
    assert_eq!(mirror_two.instance_id, matte_two.instance_id, "reflectivity must not move geometry");
    // Floor pixels whose colour changed visibly: where the sphere is mirrored, and elsewhere
    // where the floor now also mirrors the sky.
    let changed = (0..matte_two.pixel_count())
        .filter(|&i| matte_two.instance_id[i] == FLOOR)
        .filter(|&i| (mirror_two.color[i] - matte_two.color[i]).abs().max_element() > 0.05)
        .count();
    let floor = matte_two.instance_id.iter().filter(|&&id| id == FLOOR).count();
    assert!(changed > floor / 4, "only {changed} of {floor} floor pixels changed with reflectivity 0.5");
    // The mirrored sphere shows under the model: those floor pixels reflect sphere colour.
    let reddish = (0..matte_two.pixel_count())
        .filter(|&i| matte_two.instance_id[i] == FLOOR)
        .filter(|&i| {
            mirror_two.color[i].x - mirror_two.color[i].z > matte_two.color[i].x - matte_two.color[i].z + 0.05
        })
        .count();
    assert!(reddish > 100, "only {reddish} floor pixels picked up the sphere's red reflection");
    assert_no_validation_messages(&renderer);
}
