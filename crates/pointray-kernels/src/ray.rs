//! A ray: `origin + t * direction`. Twin of `shaders/ray.glsl`.

use glam::Vec3;

/// The direction need not be unit length: a world ray brought into an object's space
/// keeps its parameter `t`, so hits found there are at the same `t` in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
}

impl Ray {
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self { origin, direction }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}
