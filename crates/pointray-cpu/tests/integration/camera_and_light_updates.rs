//! Moving the camera or the lights of a built renderer (no BVH rebuilt) draws exactly the
//! frame that a renderer built afresh for the moved scene draws: shadows and reflections
//! included, so every kind of ray sees the change.

use crate::common;

use common::*;
use glam::{Affine3A, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_scene::{Camera, Light, Material, RenderSettings, RenderedImage, Scene};

fn reflective_floor_and_sphere(camera: Camera, lights: Vec<Light>) -> Scene {
    let sphere = patches_object(
        "sphere",
        sphere_patches(0.5, 2000),
        Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0)),
        matte(),
    );
    let floor = mesh_object("floor", floor_mesh(3.0), Material { reflectivity: 0.4, ..matte() });
    scene(camera, lights, vec![floor, sphere])
}

fn settings() -> RenderSettings {
    RenderSettings { width: 64, height: 48, samples_per_pixel: 2, max_depth: 3, ..RenderSettings::default() }
}

fn front_camera() -> Camera {
    camera(Vec3::new(0.0, 3.0, 4.0), Vec3::new(0.0, 0.5, 0.0))
}

fn side_camera() -> Camera {
    camera(Vec3::new(-3.5, 1.5, 1.0), Vec3::new(0.0, 0.8, 0.0))
}

fn overhead_light() -> Vec<Light> {
    vec![Light::point(Vec3::new(0.3, 4.0, 0.2), Vec3::ONE, 1.0)]
}

/// A different point light and a directional one: the list changes length as well as place.
fn two_low_lights() -> Vec<Light> {
    vec![
        Light::point(Vec3::new(2.5, 1.5, -1.0), Vec3::new(1.0, 0.8, 0.6), 0.9),
        Light::Directional { direction: Vec3::new(1.0, -1.0, 0.5), color: Vec3::ONE, intensity: 0.4 },
    ]
}

fn fresh_render(camera: Camera, lights: Vec<Light>) -> RenderedImage {
    CpuRenderer::new(&reflective_floor_and_sphere(camera, lights)).render(&settings())
}

#[test]
fn a_moved_camera_draws_the_fresh_renderers_frame() {
    let mut renderer = CpuRenderer::new(&reflective_floor_and_sphere(front_camera(), overhead_light()));
    let before = renderer.render(&settings());
    renderer.set_camera(side_camera());
    let moved = renderer.render(&settings());
    assert_ne!(moved.color, before.color, "the new camera sees a different image");
    assert!(
        moved == fresh_render(side_camera(), overhead_light()),
        "moved camera differs from a fresh build"
    );
}

#[test]
fn moved_lights_draw_the_fresh_renderers_frame() {
    let mut renderer = CpuRenderer::new(&reflective_floor_and_sphere(front_camera(), overhead_light()));
    let before = renderer.render(&settings());
    renderer.set_lights(two_low_lights());
    let moved = renderer.render(&settings());
    assert_ne!(moved.color, before.color, "the new lights shade a different image");
    assert_eq!(moved.depth, before.depth, "lights are not geometry: the same surfaces are hit");
    assert!(
        moved == fresh_render(front_camera(), two_low_lights()),
        "moved lights differ from a fresh build"
    );
}

#[test]
fn moving_back_restores_the_first_frame() {
    let mut renderer = CpuRenderer::new(&reflective_floor_and_sphere(front_camera(), overhead_light()));
    let first = renderer.render(&settings());
    renderer.set_camera(side_camera());
    renderer.set_lights(two_low_lights());
    assert!(
        renderer.render(&settings()) == fresh_render(side_camera(), two_low_lights()),
        "camera and lights moved together differ from a fresh build"
    );
    renderer.set_camera(front_camera());
    renderer.set_lights(overhead_light());
    assert!(renderer.render(&settings()) == first, "moving back does not restore the first frame");
}
