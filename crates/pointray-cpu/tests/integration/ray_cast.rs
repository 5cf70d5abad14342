//! Rays aimed by the caller: the nearest of two objects, its index and distance, and the
//! range limits.

use crate::common;

use common::*;
use glam::{Affine3A, Vec3};
use pointray_cpu::CpuRenderer;
use pointray_kernels::Ray;
use pointray_scene::AcceptanceTest;

/// A triangle floor at y = 0 and a patch plane at y = 1 above it, both 2 wide.
fn two_floors() -> CpuRenderer {
    let floor = mesh_object("floor", floor_mesh(1.0), matte());
    let raised = Affine3A::from_translation(Vec3::Y);
    let shelf = patches_object("shelf", plane_patches(1.0, 21), raised, matte());
    CpuRenderer::new(&scene(camera(Vec3::splat(3.0), Vec3::ZERO), vec![], vec![floor, shelf]))
}

#[test]
fn a_cast_ray_reports_the_nearest_object_and_its_distance() {
    let renderer = two_floors();
    let down = Ray::new(Vec3::new(0.2, 3.0, -0.1), Vec3::NEG_Y);
    for acceptance in [AcceptanceTest::Box, AcceptanceTest::Disk] {
        let shelf = renderer.cast(&down, 0.0, f32::INFINITY, acceptance).expect("the shelf is below");
        assert_eq!(shelf.object, 1);
        assert!((shelf.t - 2.0).abs() < 1e-4, "{shelf:?}");
        // Past the shelf, the floor.
        let floor = renderer.cast(&down, 2.5, f32::INFINITY, acceptance).expect("the floor is below");
        assert_eq!(floor.object, 0);
        assert!((floor.t - 3.0).abs() < 1e-5, "{floor:?}");
        assert!(floor.primitive < 2);
    }
}

#[test]
fn a_cast_ray_misses_beyond_its_range_and_outside_the_objects() {
    let renderer = two_floors();
    let down = Ray::new(Vec3::new(0.2, 3.0, -0.1), Vec3::NEG_Y);
    assert_eq!(renderer.cast(&down, 0.0, 1.5, AcceptanceTest::Disk), None);
    let beside = Ray::new(Vec3::new(5.0, 3.0, 0.0), Vec3::NEG_Y);
    assert_eq!(renderer.cast(&beside, 0.0, f32::INFINITY, AcceptanceTest::Disk), None);
}
