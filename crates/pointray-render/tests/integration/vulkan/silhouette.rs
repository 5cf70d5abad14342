//! The bunny as points (prepped into patches) covers the same pixels as the bunny mesh.
//!
//! Measured here (lavapipe, 256x256): IoU 0.988 with the disk acceptance test and 0.979 with
//! the box test, whose patches reach past the silhouette (every extra pixel was a point-set
//! pixel, none a hole). The disk test is the one METHOD.md §3 step 3 keeps for having fewer
//! false surfaces, so it carries the 0.98 requirement; the box test is held to 0.97.

use pointray_io::formats::ply::read_triangle_mesh;
use pointray_scene::{Material, PatchAcceptance, RenderSettings, RenderedImage};
use pointray_test_support::floor_scenes::{iou, mesh, model_on_floor, object, settings};
use pointray_test_support::{assert_no_validation_messages, prepped_points, vulkan_renderer};

const MODEL: u32 = 0;

fn model_mask(frame: &RenderedImage) -> Vec<bool> {
    frame.instance_id.iter().map(|&id| id == MODEL).collect()
}

#[test]
fn bunny_points_and_bunny_mesh_have_the_same_silhouette() {
    let points_path = pointray_test_support::data_file("points/bunny.ply");
    let mesh_path = pointray_test_support::data_file("meshes/bunny.ply");
    let Some(renderer) = vulkan_renderer() else { return };
    let bunny_mesh = read_triangle_mesh(&mesh_path).expect("the bunny mesh loads");
    let mesh_object = object("bunny mesh", mesh(bunny_mesh), Material::default());
    let bounds = mesh_object.world_bounds().expect("the mesh has vertices");
    let points = prepped_points("bunny points", &points_path, Material::default());

    let base = settings(256);
    let mesh_mask = model_mask(
        &renderer.render(&model_on_floor(mesh_object, bounds, 0.0), &base).expect("the mesh renders"),
    );
    let covered = mesh_mask.iter().filter(|m| **m).count();
    assert!(covered > 5000, "the bunny covers only {covered} pixels");
    let prepared = renderer.prepare(&model_on_floor(points, bounds, 0.0)).expect("the points upload");
    for (acceptance, required) in [(PatchAcceptance::Disk, 0.98), (PatchAcceptance::Box, 0.97)] {
        let settings = RenderSettings { acceptance, ..base };
        let points_mask = model_mask(&renderer.trace(&prepared, &settings).expect("the points render"));
        let overlap = iou(&points_mask, &mesh_mask);
        eprintln!("bunny silhouette IoU with {acceptance:?}: {overlap:.4} over {covered} mesh pixels");
        assert!(overlap >= required, "silhouette IoU {overlap:.4} < {required} with {acceptance:?}");
    }
    assert_no_validation_messages(&renderer);
}
