//! Floor pixels in the model's shadow are darker than lit ones; with the light off they
//! are not.

use crate::common;

use common::{
    assert_no_validation_messages, mean_luminance, primary_ray, renderer, settings, sphere_on_floor,
};
use glam::Vec3;
use pointray_scene::{Light, RenderedImage, Scene};

const FLOOR: u32 = 1;

/// Whether the segment from `point` to `light` passes through the unit sphere at (0, 1, 0).
fn sphere_blocks(point: Vec3, light: Vec3) -> bool {
    let to_light = light - point;
    let direction = to_light.normalize();
    let offset = point - Vec3::Y;
    let b = offset.dot(direction);
    let c = offset.length_squared() - 1.0;
    let disc = b * b - c;
    disc > 0.0 && {
        let t = -b - disc.sqrt();
        t > 0.0 && t < to_light.length()
    }
}

fn light_position(scene: &Scene) -> Vec3 {
    match scene.lights[0] {
        Light::Point { position, .. } => position,
        _ => unreachable!("the test scene has a point light"),
    }
}

/// Floor pixels split by whether the sphere shadows them (from the geometry).
fn floor_pixels(scene: &Scene, image: &RenderedImage) -> (Vec<bool>, Vec<bool>) {
    let light = light_position(scene);
    let shadowed: Vec<bool> = (0..image.pixel_count())
        .map(|i| {
            image.instance_id[i] == FLOOR
                && sphere_blocks(primary_ray(&scene.camera, image, i).at(image.depth[i]), light)
        })
        .collect();
    let lit = (0..image.pixel_count()).map(|i| image.instance_id[i] == FLOOR && !shadowed[i]).collect();
    (shadowed, lit)
}

#[test]
fn the_shadow_is_darker_and_vanishes_with_the_light_off() {
    let Some(renderer) = renderer() else { return };
    let settings = settings(128);
    let lit_scene = sphere_on_floor(0.0, 1.0);
    let image = renderer.render(&lit_scene, &settings).expect("renders");
    let (shadowed, lit) = floor_pixels(&lit_scene, &image);
    assert!(shadowed.iter().filter(|s| **s).count() > 100, "the shadow should cover floor pixels");
    let (in_shadow, in_light) = (mean_luminance(&image, |i| shadowed[i]), mean_luminance(&image, |i| lit[i]));
    assert!(in_shadow < 0.5 * in_light, "shadowed floor {in_shadow} is not darker than lit floor {in_light}");

    let dark_scene = sphere_on_floor(0.0, 0.0);
    let image = renderer.render(&dark_scene, &settings).expect("renders");
    let (shadowed, lit) = floor_pixels(&dark_scene, &image);
    let (in_shadow, in_light) = (mean_luminance(&image, |i| shadowed[i]), mean_luminance(&image, |i| lit[i]));
    assert!(
        (in_shadow - in_light).abs() < 1e-4,
        "with the light off: shadowed {in_shadow} vs lit {in_light}"
    );
    assert_no_validation_messages(&renderer);
}
