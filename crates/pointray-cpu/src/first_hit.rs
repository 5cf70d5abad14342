//! The first surface a single ray meets, for callers that cast their own rays (a LiDAR
//! simulator, picking) rather than render a frame.

use glam::Vec3;
use pointray_kernels::{Ray, face_forward};
use pointray_scene::PatchAcceptance;

use crate::renderer::CpuRenderer;

/// What a ray met first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The ray parameter of the hit: a distance when the ray's direction has unit length.
    pub t: f32,
    /// The object's index in `Scene::objects`.
    pub object: u32,
    /// The patch or triangle index within the object.
    pub primitive: u32,
    /// The surface's world normal at the hit, unit length, turned to face the ray's origin.
    pub normal: Vec3,
}

impl CpuRenderer {
    /// The nearest surface on `ray` within `[t_min, t_max]`, through the same BVHs and
    /// intersection tests as a rendered frame's primary rays.
    pub fn first_hit(&self, ray: &Ray, t_min: f32, t_max: f32, test: PatchAcceptance) -> Option<RayHit> {
        let hit = self.top.closest_hit(ray, t_min, t_max, test)?;
        let instance = &self.top.instances[hit.instance];
        let normal = face_forward(instance.normal_to_world(self.object_normal(&hit)), ray.direction);
        Some(RayHit { t: hit.t, object: instance.object_index, primitive: hit.primitive, normal })
    }
}
