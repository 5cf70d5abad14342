//! The top level: a BVH over the world boxes of the scene's object instances, one per
//! tile of a large point set.

use glam::Vec2;
use obvhs::cwbvh::CwBvh;
use pointray_kernels::{PatchAcceptance, Ray};
use pointray_scene::Scene;

use crate::instance::Instance;
use crate::object_bvh::{build_bvh, traversal_ray};

/// A hit in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit {
    pub t: f32,
    /// Index into `TopLevel::instances`.
    pub instance: usize,
    pub primitive: u32,
    pub uv: Vec2,
}

pub struct TopLevel {
    pub instances: Vec<Instance>,
    /// `None` when no object has anything to hit.
    bvh: Option<CwBvh>,
}

impl TopLevel {
    /// Every object's tiles as instances; point sets in tiles of at most `max_tile_patches`.
    pub fn build(scene: &Scene, max_tile_patches: usize) -> Self {
        let instances: Vec<Instance> = scene
            .objects
            .iter()
            .enumerate()
            .flat_map(|(index, object)| Instance::tiles_of(index as u32, object, max_tile_patches))
            .collect();
        let boxes: Vec<obvhs::aabb::Aabb> = instances
            .iter()
            .map(|instance| {
                let bounds = instance.world_bounds();
                obvhs::aabb::Aabb::new(bounds.min.into(), bounds.max.into())
            })
            .collect();
        let bvh = (!boxes.is_empty()).then(|| build_bvh(&boxes));
        Self { instances, bvh }
    }

    /// The nearest hit of a world ray in `[t_min, t_max]`.
    pub fn closest_hit(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        acceptance: PatchAcceptance,
    ) -> Option<SceneHit> {
        let bvh = self.bvh.as_ref()?;
        let mut nearest = None;
        let mut hit = obvhs::ray::RayHit::none();
        bvh.ray_traverse(traversal_ray(ray, t_min, t_max), &mut hit, |candidate, id| {
            let instance = bvh.primitive_indices[id] as usize;
            match self.instances[instance].closest_hit(ray, candidate.tmin, candidate.tmax, acceptance) {
                Some(found) if found.t < candidate.tmax => {
                    nearest =
                        Some(SceneHit { t: found.t, instance, primitive: found.primitive, uv: found.uv });
                    found.t
                }
                _ => f32::INFINITY,
            }
        });
        nearest
    }

    /// Whether anything lies on the world ray within `[t_min, t_max]` (any hit ends the search).
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, acceptance: PatchAcceptance) -> bool {
        let Some(bvh) = self.bvh.as_ref() else { return false };
        !bvh.ray_traverse_miss(traversal_ray(ray, t_min, t_max), |candidate, id| {
            let instance = &self.instances[bvh.primitive_indices[id] as usize];
            if instance.occludes(ray, candidate.tmin, candidate.tmax, acceptance) {
                candidate.tmin
            } else {
                f32::INFINITY
            }
        })
    }
}
