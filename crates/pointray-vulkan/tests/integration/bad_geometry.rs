//! A scene built in code with geometry the device cannot build on (NaN or 1e38 boxes, a
//! vertex at infinity) is refused with an error naming the object, before any upload.

use glam::Vec3;
use pointray_kernels::{COLOR_NEIGHBORS, NO_NEIGHBOR};
use pointray_scene::{Material, Scene};

use crate::common::{floor, mesh, object, patches, renderer, settings, sphere_on_floor, sphere_patches};

fn with_object(name: &str, geometry: pointray_scene::Geometry) -> Scene {
    let mut scene = sphere_on_floor(0.0, 1.0);
    scene.objects.push(object(name, geometry, Material::default()));
    scene
}

#[test]
fn out_of_range_geometry_is_refused_by_object_name() {
    let Some(renderer) = renderer() else { return };
    let mut nan_box = sphere_patches(Vec3::ZERO, 1.0, 200);
    nan_box.aabbs[17].min[0] = f32::NAN;
    let mut huge_box = sphere_patches(Vec3::ZERO, 1.0, 200);
    huge_box.aabbs[0].max = [1e38; 3];
    let mut far_floor = floor(0.0, 1.0);
    far_floor.positions[2] = Vec3::INFINITY;
    for (name, geometry) in
        [("nan box", patches(nan_box)), ("huge box", patches(huge_box)), ("far floor", mesh(far_floor))]
    {
        let error = renderer.render(&with_object(name, geometry), &settings(16)).unwrap_err().to_string();
        assert!(error.contains(name) && error.contains("out of range"), "{name}: {error}");
    }
    let fine = renderer.render(&sphere_on_floor(0.0, 1.0), &settings(16));
    assert!(fine.is_ok(), "the renderer still renders good scenes");
}

#[test]
fn a_colour_neighbour_outside_its_set_is_refused_by_patch() {
    let Some(renderer) = renderer() else { return };
    let mut sphere = sphere_patches(Vec3::ZERO, 1.0, 200);
    let mut neighbors = vec![NO_NEIGHBOR; sphere.len() * COLOR_NEIGHBORS];
    neighbors[150 * COLOR_NEIGHBORS + 2] = sphere.len() as u32 + 5;
    sphere.color_neighbors = neighbors.into();
    let error =
        renderer.render(&with_object("stray", patches(sphere)), &settings(16)).unwrap_err().to_string();
    assert!(error.contains("patch 150 names colour neighbour 205"), "{error}");
}
