//! The scene's emissive mesh triangles in world space: the light that next-event estimation
//! draws for them. Emissive point sets are left to the paths that meet them.

use pointray_kernels::EmissiveTriangles;

use crate::{Geometry, Scene};

impl Scene {
    pub fn emissive_triangles(&self) -> EmissiveTriangles {
        let emitting = self.objects.iter().filter(|object| object.material.emission != glam::Vec3::ZERO);
        EmissiveTriangles::new(emitting.flat_map(|object| {
            let Geometry::Mesh(mesh) = &object.geometry else { return Vec::new() };
            (0..mesh.triangles.len())
                .map(|t| {
                    let corners = mesh.triangles[t]
                        .map(|i| object.transform.transform_point3(mesh.positions[i as usize]));
                    (corners, object.material.emission)
                })
                .collect()
        }))
    }
}
