//! A direction drawn from a BSDF. Twin of `shaders/bsdf_sample.glsl`.

use glam::Vec3;

/// `direction` is local (the shading normal along +z); `weight` is `f cos θ / pdf`, zero when
/// the draw failed (a direction below the surface, total internal reflection of a
/// transmission); `pdf` is per steradian, or 0 for a delta lobe (`delta`), which only
/// sampling reaches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    pub direction: Vec3,
    pub weight: Vec3,
    pub pdf: f32,
    pub delta: bool,
}

impl BsdfSample {
    /// A failed draw: the path ends.
    pub const NONE: Self = Self { direction: Vec3::Z, weight: Vec3::ZERO, pdf: 0.0, delta: false };
}
