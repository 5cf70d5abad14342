//! `CpuRenderer::first_hit`: one ray's nearest surface, with its object, distance and a
//! normal facing the ray, through meshes and patches alike.

use crate::common;

use common::*;
use glam::{Affine3A, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_kernels::Ray;
use pointray_scene::PatchAcceptance;

/// A floor mesh at y = 0 (object 0) and a point-set plane lifted to y = 1 over half of it
/// (object 1).
fn two_layers() -> CpuRenderer {
    let floor = mesh_object("floor", floor_mesh(4.0), matte());
    let lifted = Affine3A::from_translation(Vec3::new(1.5, 1.0, 0.0));
    let upper = patches_object("upper", plane_patches(1.0, 21), lifted, matte());
    CpuRenderer::new(&scene(camera(Vec3::new(0.0, 5.0, 5.0), Vec3::ZERO), vec![], vec![floor, upper]))
}

#[test]
fn the_nearest_surface_wins_and_its_normal_faces_the_ray() {
    let renderer = two_layers();
    let down = |x: f32| Ray::new(Vec3::new(x, 3.0, 0.2), Vec3::NEG_Y);
    let over_patches = renderer.first_hit(&down(1.5), 0.0, f32::INFINITY, PatchAcceptance::Disk).unwrap();
    assert_eq!(over_patches.object, 1);
    assert!((over_patches.t - 2.0).abs() < 1e-4, "t = {}", over_patches.t);
    assert!((over_patches.normal - Vec3::Y).length() < 1e-4, "normal = {}", over_patches.normal);

    let over_floor = renderer.first_hit(&down(-2.0), 0.0, f32::INFINITY, PatchAcceptance::Disk).unwrap();
    assert_eq!(over_floor.object, 0);
    assert!((over_floor.t - 3.0).abs() < 1e-5);
    let from_below = Ray::new(Vec3::new(-2.0, -1.0, 0.2), Vec3::Y);
    let under = renderer.first_hit(&from_below, 0.0, f32::INFINITY, PatchAcceptance::Disk).unwrap();
    assert!((under.normal - Vec3::NEG_Y).length() < 1e-5, "the normal must face the ray's origin");
}

#[test]
fn nothing_beyond_t_max_or_off_the_surfaces() {
    let renderer = two_layers();
    let down = Ray::new(Vec3::new(-2.0, 3.0, 0.2), Vec3::NEG_Y);
    assert_eq!(renderer.first_hit(&down, 0.0, 2.5, PatchAcceptance::Disk), None);
    let sideways = Ray::new(Vec3::new(-2.0, 3.0, 0.2), Vec3::X);
    assert_eq!(renderer.first_hit(&sideways, 0.0, f32::INFINITY, PatchAcceptance::Disk), None);
}
