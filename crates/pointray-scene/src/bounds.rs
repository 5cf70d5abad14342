//! World-space bounds of objects and scenes, taken over their surface samples: a mesh's
//! vertices and a point set's patch origins (the fitted points), each placed by the object's
//! transform. Patch boxes are left out on purpose: they are traversal aids that reach past the
//! surface, and a ground placed under them would float below the model.

use glam::{Affine3A, Vec3};
use pointray_kernels::Aabb;
use rayon::prelude::*;

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

    /// The smallest box holding the surface samples mapped by `place`, or `None` for no
    /// samples. Taken on every core: a large point set has 10^8 samples or more, and a scene
    /// takes its bounds several times on its way to a renderer.
    pub fn sample_bounds(&self, place: impl Fn(Vec3) -> Vec3 + Sync + Send) -> Option<Aabb> {
        let point_box = |p: Vec3| {
            let p = place(p);
            Aabb::new(p, p)
        };
        let union = |a: Aabb, b: Aabb| a.union(&b);
        match self {
            Geometry::Patches(patches) => {
                patches.hot.par_iter().map(|patch| point_box(patch.origin())).reduce_with(union)
            }
            Geometry::Mesh(mesh) => mesh.positions.par_iter().map(|&p| point_box(p)).reduce_with(union),
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
    geometry.sample_bounds(|p| transform.transform_point3(p))
}
