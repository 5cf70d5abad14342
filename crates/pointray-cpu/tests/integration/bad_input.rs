//! Broken objects are left out of the render instead of crashing it.

use crate::common;

use common::*;
use glam::{Affine3A, Vec3};
use pointray_cpu::render;
use pointray_io::TriangleMesh;
use pointray_scene::{RenderSettings, RenderedImage};

fn settings() -> RenderSettings {
    RenderSettings { width: 16, height: 16, ..RenderSettings::default() }
}

#[test]
fn broken_objects_are_left_out_and_good_ones_still_render() {
    let flattened = patches_object("flat", plane_patches(1.0, 5), Affine3A::from_scale(Vec3::ZERO), matte());
    let dangling = mesh_object(
        "dangling",
        TriangleMesh { positions: vec![Vec3::ZERO; 2], triangles: vec![[0, 1, 7]] },
        matte(),
    );
    let empty = patches_object("empty", patch_set(vec![]), Affine3A::IDENTITY, matte());
    let floor = mesh_object("floor", floor_mesh(10.0), matte());
    let scene =
        scene(camera(Vec3::new(0.0, 3.0, 3.0), Vec3::ZERO), vec![], vec![flattened, dangling, empty, floor]);
    let image = render(&scene, &settings());
    assert!(image.instance_id.iter().all(|&id| id == 3 || id == RenderedImage::MISS));
    assert!(image.instance_id.contains(&3), "the floor should still be visible");
}

#[test]
fn non_finite_and_huge_geometry_is_left_out_instead_of_panicking_the_bvh_build() {
    let mut nan_boxes = plane_patches(1.0, 5);
    nan_boxes.aabbs[2].min = [f32::NAN; 3];
    let mut huge_boxes = plane_patches(1.0, 5);
    huge_boxes.aabbs[0] = pointray_kernels::Aabb::new(Vec3::splat(-1e38), Vec3::splat(1e38));
    let huge_mesh =
        TriangleMesh { positions: vec![Vec3::ZERO, Vec3::X * 1e38, Vec3::Z], triangles: vec![[0, 1, 2]] };
    let far = patches_object("far", plane_patches(1.0, 5), Affine3A::from_scale(Vec3::splat(1e30)), matte());
    let objects = vec![
        patches_object("nan", nan_boxes, Affine3A::IDENTITY, matte()),
        patches_object("huge", huge_boxes, Affine3A::IDENTITY, matte()),
        mesh_object("huge mesh", huge_mesh, matte()),
        far,
        mesh_object("floor", floor_mesh(10.0), matte()),
    ];
    let scene = scene(camera(Vec3::new(0.0, 3.0, 3.0), Vec3::ZERO), vec![], objects);
    let image = render(&scene, &settings());
    assert!(image.instance_id.iter().all(|&id| id == 4 || id == RenderedImage::MISS));
    assert!(image.instance_id.contains(&4), "the floor should still be visible");
}

#[test]
fn an_empty_scene_is_all_background() {
    let scene = scene(camera(Vec3::new(0.0, 3.0, 3.0), Vec3::ZERO), vec![], vec![]);
    let image = render(&scene, &settings());
    assert!(image.color.iter().all(|&c| c == BACKGROUND));
    assert!(image.depth.iter().all(|d| d.is_infinite()));
}
