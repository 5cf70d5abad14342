//! The bunny as points (prepped into patches) covers the same pixels as the bunny mesh.
//!
//! Measured here (lavapipe, 256x256): IoU 0.988 with the disk acceptance test and 0.979 with
//! the box test, whose patches reach past the silhouette (every extra pixel was a point-set
//! pixel, none a hole). The disk test is the one SPEC.md §3 step 3 keeps for having fewer
//! false surfaces, so it carries the 0.98 requirement; the box test is held to 0.97.

mod common;

use std::sync::Arc;

use common::{
    assert_no_validation_messages, data_file, floor, iou, mesh, object, point_light, renderer, settings,
};
use glam::{Affine3A, Vec3};
use pointray_io::formats::ply::{read_point_cloud, read_triangle_mesh};
use pointray_kernels::Aabb;
use pointray_scene::{
    AcceptanceTest, Background, Frame, Geometry, Material, RenderSettings, Scene, SceneObject,
};
use pointray_surface::{NoProgress, PrepOptions, prep};

const MODEL: u32 = 0;

/// The model on a floor just under it, framed from the front and a little above.
fn on_floor(model: SceneObject, bounds: Aabb) -> Scene {
    let size = (Vec3::from(bounds.max) - Vec3::from(bounds.min)).max_element();
    Scene {
        camera: Scene::framing_camera(&bounds, Vec3::new(0.3, 0.4, 1.0), 40.0, 1.0),
        lights: vec![point_light(Vec3::from(bounds.max) + Vec3::splat(size), 1.0)],
        background: Background::Solid(Vec3::splat(0.2)),
        objects: vec![model, object("floor", mesh(floor(bounds.min[1], 4.0 * size)), Material::default())],
    }
}

fn model_mask(frame: &Frame) -> Vec<bool> {
    frame.instance_id.iter().map(|&id| id == MODEL).collect()
}

#[test]
fn bunny_points_and_bunny_mesh_have_the_same_silhouette() {
    let (Some(points_path), Some(mesh_path)) = (data_file("points/bunny.ply"), data_file("meshes/bunny.ply"))
    else {
        return;
    };
    let Some(renderer) = renderer() else { return };
    let cloud = read_point_cloud(&points_path).expect("the bunny points load");
    let (patches, _) = prep(&cloud, &PrepOptions::default(), &NoProgress).expect("prep succeeds");
    let bunny_mesh = read_triangle_mesh(&mesh_path).expect("the bunny mesh loads");
    let mesh_object = object("bunny mesh", mesh(bunny_mesh), Material::default());
    let bounds = mesh_object.world_bounds().expect("the mesh has vertices");
    let points = SceneObject {
        name: "bunny points".into(),
        // prep recentred the points; the offset puts them back where the mesh is.
        transform: Affine3A::from_translation(patches.offset.as_vec3()),
        material: Material::default(),
        geometry: Geometry::Patches(Arc::new(patches)),
    };

    let base = settings(256);
    let mesh_mask =
        model_mask(&renderer.render(&on_floor(mesh_object, bounds), &base).expect("the mesh renders"));
    let covered = mesh_mask.iter().filter(|m| **m).count();
    assert!(covered > 5000, "the bunny covers only {covered} pixels");
    let prepared = renderer.prepare(&on_floor(points, bounds)).expect("the points upload");
    for (acceptance, required) in [(AcceptanceTest::Disk, 0.98), (AcceptanceTest::Box, 0.97)] {
        let settings = RenderSettings { acceptance, ..base };
        let points_mask = model_mask(&renderer.trace(&prepared, &settings).expect("the points render"));
        let overlap = iou(&points_mask, &mesh_mask);
        eprintln!("bunny silhouette IoU with {acceptance:?}: {overlap:.4} over {covered} mesh pixels");
        assert!(overlap >= required, "silhouette IoU {overlap:.4} < {required} with {acceptance:?}");
    }
    assert_no_validation_messages(&renderer);
}
