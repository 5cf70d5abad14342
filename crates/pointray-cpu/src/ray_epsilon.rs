//! The offset of secondary-ray origins, per the rendering contract: `1e-4 x` the diagonal
//! of the scene's world bounds over its surface samples (patch origins, mesh vertices).
//!
//! This repeats the definition of `Scene::ray_epsilon()`, which the scene crate is adding;
//! it lives here until that lands, and must match it (both backends use the same offset).

use glam::Vec3;
use pointray_scene::{Geometry, Scene};

const RAY_EPSILON_FRACTION: f32 = 1e-4;

/// `1e-4 x` the world bounds' diagonal; a scene without extent uses a diagonal of 1.
pub fn ray_epsilon(scene: &Scene) -> f32 {
    let mut min = Vec3::INFINITY;
    let mut max = Vec3::NEG_INFINITY;
    for object in &scene.objects {
        for point in surface_samples(&object.geometry) {
            let world = object.transform.transform_point3(point);
            min = min.min(world);
            max = max.max(world);
        }
    }
    let diagonal = (max - min).length();
    let diagonal = if diagonal.is_finite() && diagonal > 0.0 { diagonal } else { 1.0 };
    RAY_EPSILON_FRACTION * diagonal
}

fn surface_samples(geometry: &Geometry) -> Box<dyn Iterator<Item = Vec3> + '_> {
    match geometry {
        Geometry::Patches(patches) => Box::new(patches.hot.iter().map(|patch| patch.origin())),
        Geometry::Mesh(mesh) => Box::new(mesh.positions.iter().copied()),
    }
}
