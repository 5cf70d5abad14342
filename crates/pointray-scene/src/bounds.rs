//! World-space bounds of objects and scenes, taken over their surface samples: a mesh's
//! vertices and a point set's patch origins (the fitted points), each placed by the object's
//! transform. Patch boxes are left out on purpose: they are traversal aids that reach past the
//! surface, and a ground placed under them would float below the model.

use glam::{Affine3A, Vec3};
use pointray_kernels::Aabb;

use crate::{Geometry, SceneObject};

/// The smallest box holding every point, or `None` for no points.
pub fn bounds_of_points(points: impl IntoIterator<Item = Vec3>) -> Option<Aabb> {
    points.into_iter().fold(None, |bounds, p| {
        Some(match bounds {
            None => Aabb::new(p, p),
            Some(b) => Aabb::new(Vec3::from(b.min).min(p), Vec3::from(b.max).max(p)),
        })
    })
}

pub fn center(bounds: &Aabb) -> Vec3 {
    (Vec3::from(bounds.min) + Vec3::from(bounds.max)) * 0.5
}

pub fn extent(bounds: &Aabb) -> Vec3 {
    Vec3::from(bounds.max) - Vec3::from(bounds.min)
}

pub fn diagonal(bounds: &Aabb) -> f32 {
    extent(bounds).length()
}

impl Geometry {
    /// The surface samples in object coordinates.
    pub fn local_points(&self) -> Box<dyn Iterator<Item = Vec3> + '_> {
        match self {
            Geometry::Patches(patches) => Box::new(patches.hot.iter().map(|patch| patch.origin())),
            Geometry::Mesh(mesh) => Box::new(mesh.positions.iter().copied()),
        }
    }
}

impl SceneObject {
    /// World bounds of the object's surface samples; `None` when it has none.
    pub fn world_bounds(&self) -> Option<Aabb> {
        transformed_bounds(&self.geometry, &self.transform)
    }
}

pub(crate) fn transformed_bounds(geometry: &Geometry, transform: &Affine3A) -> Option<Aabb> {
    bounds_of_points(geometry.local_points().map(|p| transform.transform_point3(p)))
}
