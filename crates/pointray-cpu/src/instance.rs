//! An object placed in the world: its bottom-level BVH and its transforms.

use glam::{Affine3A, Mat3A, Vec3};
use pointray_kernels::{Aabb, PatchAcceptance, Ray};
use pointray_patches::geometry_range::box_in_range;
use pointray_scene::SceneObject;

use crate::object_bvh::{ObjectBvh, ObjectHit};

pub struct Instance {
    /// The object's index in `Scene::objects` (the `instance_id` AOV).
    pub object_index: u32,
    pub blas: ObjectBvh,
    world_to_object: Affine3A,
    /// Object normals to world: the inverse transpose of the object-to-world linear part.
    normal_to_world: Mat3A,
    world_bounds: Aabb,
}

impl Instance {
    /// The instances of an object's tiles (one for a mesh or a small point set, at most
    /// `max_tile_patches` patches each), all with the object's transform. None for an
    /// object with nothing to hit or a transform that cannot be inverted (a zero scale
    /// flattens it to nothing visible).
    pub fn tiles_of(object_index: u32, object: &SceneObject, max_tile_patches: usize) -> Vec<Self> {
        if object.transform.matrix3.determinant().abs() <= f32::MIN_POSITIVE || !object.transform.is_finite()
        {
            tracing::warn!("CPU renderer: object {:?} has a singular transform; left out", object.name);
            return Vec::new();
        }
        let world_to_object = object.transform.inverse();
        let instances: Vec<Self> = ObjectBvh::build_tiles(&object.geometry, max_tile_patches)
            .into_iter()
            .map(|blas| Self {
                object_index,
                world_bounds: transformed_box(&blas.bounds(), &object.transform),
                blas,
                world_to_object,
                normal_to_world: world_to_object.matrix3.transpose(),
            })
            .collect();
        if instances.iter().any(|instance| !box_in_range(&instance.world_bounds)) {
            tracing::warn!("CPU renderer: object {:?} is placed beyond the f32 range; left out", object.name);
            return Vec::new();
        }
        instances
    }

    /// Object lengths to world lengths, exact for uniform scales. Taken from the inverse
    /// transform's first column, as the GPU's closest-hit shader does.
    pub fn world_scale(&self) -> f32 {
        1.0 / self.world_to_object.matrix3.x_axis.length()
    }

    pub fn world_bounds(&self) -> Aabb {
        self.world_bounds
    }

    /// The world ray in object space. The direction is not renormalised, so `t` is the
    /// same in both spaces.
    pub fn to_object(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.world_to_object.transform_point3(ray.origin),
            self.world_to_object.transform_vector3(ray.direction),
        )
    }

    pub fn closest_hit(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        acceptance: PatchAcceptance,
    ) -> Option<ObjectHit> {
        self.blas.closest_hit(&self.to_object(ray), t_min, t_max, acceptance)
    }

    pub fn occludes(&self, ray: &Ray, t_min: f32, t_max: f32, acceptance: PatchAcceptance) -> bool {
        self.blas.occludes(&self.to_object(ray), t_min, t_max, acceptance)
    }

    /// An object-space normal in world space, unit length.
    pub fn normal_to_world(&self, normal: Vec3) -> Vec3 {
        (self.normal_to_world * normal).normalize_or_zero()
    }
}

/// The world box around the eight corners of an object-space box.
fn transformed_box(bounds: &Aabb, transform: &Affine3A) -> Aabb {
    let (min, max) = (Vec3::from(bounds.min), Vec3::from(bounds.max));
    let corner = |index: usize| {
        let pick = |axis: usize| if index & (1 << axis) == 0 { min[axis] } else { max[axis] };
        transform.transform_point3(Vec3::new(pick(0), pick(1), pick(2)))
    };
    let first = corner(0);
    (1..8).map(corner).fold(Aabb::new(first, first), |b, p| b.union(&Aabb::new(p, p)))
}
