//! Single rays aimed by the caller rather than by a camera (a sensor's beam, a return checked
//! against the surface), traced through the same BVHs and hit tests as the frames.

use pointray_kernels::Ray;
use pointray_scene::AcceptanceTest;

use crate::renderer::{CpuRenderer, patch_acceptance};

/// The nearest surface along a cast ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The ray parameter: the distance from the origin for a unit direction.
    pub t: f32,
    /// The index of the object hit in `Scene::objects`.
    pub object: u32,
    /// The patch or triangle hit within that object.
    pub primitive: u32,
}

impl CpuRenderer {
    /// The nearest hit of `ray` with `t` in `[t_min, t_max]`, patches accepted by `acceptance`.
    pub fn cast(&self, ray: &Ray, t_min: f32, t_max: f32, acceptance: AcceptanceTest) -> Option<RayHit> {
        let hit = self.top.closest_hit(ray, t_min, t_max, patch_acceptance(acceptance))?;
        Some(RayHit {
            t: hit.t,
            object: self.top.instances[hit.instance].object_index,
            primitive: hit.primitive,
        })
    }
}
