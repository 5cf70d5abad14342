//! Per-patch records as the GPU reads them (std430), mirrored in `shaders/layout.glsl`.
//!
//! The split follows SPEC.md §2.7: `PatchHot` is all the intersection shader reads,
//! `PatchCold` is what only shading reads. Both are plain old data so that the patch
//! store, the CPU renderer and the Vulkan buffers share one byte layout.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// What the intersection test reads for patch `i`: its local frame, its six
/// quadratic coefficients and its support radius `d_i`. 64 bytes, four `vec4`s.
///
/// The frame is `(t1, t2, n)` with `t2 = n × t1`, so it is right-handed and the
/// 3x4 world-to-local matrix of the paper is recovered from origin, `t1` and `n`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchHot {
    /// `p_i` in xyz, the support radius `d_i` in w.
    pub origin_radius: [f32; 4],
    /// The first tangent `t1` in xyz, `c0` in w.
    pub tangent_c0: [f32; 4],
    /// The normal `n_i` in xyz, `c1` in w.
    pub normal_c1: [f32; 4],
    /// `c2, c3, c4, c5`.
    pub c2_c5: [f32; 4],
}

impl PatchHot {
    /// Builds a patch from its frame and `f(u,v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²`.
    pub fn new(origin: Vec3, tangent: Vec3, normal: Vec3, coefficients: [f32; 6], radius: f32) -> Self {
        let [c0, c1, c2, c3, c4, c5] = coefficients;
        Self {
            origin_radius: [origin.x, origin.y, origin.z, radius],
            tangent_c0: [tangent.x, tangent.y, tangent.z, c0],
            normal_c1: [normal.x, normal.y, normal.z, c1],
            c2_c5: [c2, c3, c4, c5],
        }
    }

    pub fn origin(&self) -> Vec3 {
        Vec3::from_slice(&self.origin_radius[..3])
    }

    pub fn radius(&self) -> f32 {
        self.origin_radius[3]
    }

    pub fn tangent_u(&self) -> Vec3 {
        Vec3::from_slice(&self.tangent_c0[..3])
    }

    pub fn tangent_v(&self) -> Vec3 {
        self.normal().cross(self.tangent_u())
    }

    pub fn normal(&self) -> Vec3 {
        Vec3::from_slice(&self.normal_c1[..3])
    }

    pub fn coefficients(&self) -> [f32; 6] {
        let [c2, c3, c4, c5] = self.c2_c5;
        [self.tangent_c0[3], self.normal_c1[3], c2, c3, c4, c5]
    }

    /// World position to local `(u, v, w)`.
    pub fn to_local(&self, world: Vec3) -> Vec3 {
        let d = world - self.origin();
        Vec3::new(d.dot(self.tangent_u()), d.dot(self.tangent_v()), d.dot(self.normal()))
    }

    /// Local `(u, v, w)` to world position.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.origin() + local.x * self.tangent_u() + local.y * self.tangent_v() + local.z * self.normal()
    }

    /// A world direction to local axes.
    pub fn direction_to_local(&self, world: Vec3) -> Vec3 {
        Vec3::new(world.dot(self.tangent_u()), world.dot(self.tangent_v()), world.dot(self.normal()))
    }

    /// A local direction to world axes.
    pub fn direction_to_world(&self, local: Vec3) -> Vec3 {
        local.x * self.tangent_u() + local.y * self.tangent_v() + local.z * self.normal()
    }
}

/// What only shading reads for patch `i`. 12 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PatchCold {
    /// Linear-space colour as RGBA8 (r in the low byte); white when the input had none.
    pub color_rgba8: u32,
    /// Scanner intensity in [0, 1]; 0 when the input had none.
    pub intensity: f32,
    /// How far the point's colour reaches in the blend of `interpolate_color`:
    /// `COLOR_SUPPORT_SCALE` times the paper's `d_i`, whatever radius the patch itself has;
    /// 0 reaches nowhere (the blend then takes the nearest point's colour).
    pub color_reach: f32,
}

impl Default for PatchCold {
    fn default() -> Self {
        Self { color_rgba8: 0xffff_ffff, intensity: 0.0, color_reach: 0.0 }
    }
}

impl PatchCold {
    pub fn from_rgb8(rgb: [u8; 3], intensity: f32) -> Self {
        Self { color_rgba8: rgb8_to_rgba8(rgb), intensity, ..Self::default() }
    }

    /// Replaces the colour, keeping the intensity and the reach.
    pub fn set_rgb8(&mut self, rgb: [u8; 3]) {
        self.color_rgba8 = rgb8_to_rgba8(rgb);
    }

    /// The colour as linear RGB in [0, 1].
    pub fn color(&self) -> Vec3 {
        let [r, g, b, _] = self.color_rgba8.to_le_bytes();
        Vec3::new(r as f32, g as f32, b as f32) / 255.0
    }
}

fn rgb8_to_rgba8(rgb: [u8; 3]) -> u32 {
    u32::from_le_bytes([rgb[0], rgb[1], rgb[2], 255])
}

/// An axis-aligned box, laid out as `VkAabbPositionsKHR`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Aabb {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Aabb {
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min: min.to_array(), max: max.to_array() }
    }

    /// The cube of half-size `half` around `center` (the paper's box, SPEC.md §2.4).
    pub fn cube(center: Vec3, half: f32) -> Self {
        Self::new(center - Vec3::splat(half), center + Vec3::splat(half))
    }

    pub fn contains(&self, p: Vec3) -> bool {
        (0..3).all(|a| p[a] >= self.min[a] && p[a] <= self.max[a])
    }

    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb::new(
            Vec3::from(self.min).min(Vec3::from(other.min)),
            Vec3::from(self.max).max(Vec3::from(other.max)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_the_glsl_strides() {
        assert_eq!(std::mem::size_of::<PatchHot>(), 64);
        assert_eq!(std::mem::size_of::<PatchCold>(), 12);
        assert_eq!(std::mem::size_of::<Aabb>(), 24);
    }

    #[test]
    fn local_and_world_round_trip() {
        let n = Vec3::new(1.0, 2.0, 2.0).normalize();
        let t = n.any_orthonormal_vector();
        let patch = PatchHot::new(Vec3::new(1.0, -2.0, 0.5), t, n, [0.0; 6], 0.1);
        let p = Vec3::new(0.3, 0.7, -1.1);
        assert!((patch.to_world(patch.to_local(p)) - p).length() < 1e-5);
        assert!(patch.tangent_u().cross(patch.tangent_v()).dot(n) > 0.999);
    }
}
