//! Per-patch records as the GPU reads them (std430), mirrored in `shaders/layout.glsl`.
//!
//! The split follows METHOD.md §2.7: `PatchHot` is all the intersection shader reads,
//! `PatchCold` is what only shading reads. Both are plain old data so that the patch
//! store, the CPU renderer and the Vulkan buffers share one byte layout.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use crate::packing::{pack_half2x16, pack_unorm2x16, unpack_half2x16, unpack_unorm2x16};
use crate::tangent_frame::{TangentFrame, pack_frame, unpack_frame, unpack_normal};

/// What the intersection test reads for patch `i`, 32 bytes (one 32-byte sector of GPU
/// memory): its surface point, its elliptical support, its tangent frame and its quadratic's
/// coefficients, packed. `decode` gives the `Patch` the maths works on.
///
/// The support is the ellipse `(u / d_u)² + (v / d_v)² <= 1` with `d_u >= d_v`, so `radius`
/// (`d_u`) also bounds the patch. An isotropic patch has `d_v = d_u`. The fit's constant term
/// `c0` is folded into the origin, which moves along the normal and leaves `(u, v)` as they
/// were, so the stored height field has `c0 = 0`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchHot {
    /// `p_i + c0 n_i`: the fitted surface over the point.
    pub origin: [f32; 3],
    /// `d_u`, the support radius along the first tangent `t1`, the larger of the two.
    pub radius: f32,
    /// The normal `n_i` and the angle of `t1` (`tangent_frame::pack_frame`).
    pub frame: u32,
    /// `d_v / d_u` (unorm16, low half) and `c1` (half float, high half).
    pub aspect_c1: u32,
    /// `c2, c3 d_u, c4 d_u, c5 d_u` as half floats, low half first: those of second order
    /// scaled by the radius so that each is of order one whatever the units, which is what
    /// half floats hold.
    pub coefficients: [u32; 2],
}

/// A patch's frame as stored: what `prep` fits in, so that the fit and the stored frame agree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PackedTangentFrame {
    word: u32,
}

impl PackedTangentFrame {
    /// The stored frame nearest to unit normal `n` with first tangent `t` (in `n`'s plane).
    pub fn new(n: Vec3, t: Vec3) -> Self {
        Self { word: pack_frame(n, t) }
    }

    /// The frame the record decodes to.
    pub fn decode(&self) -> TangentFrame {
        unpack_frame(self.word)
    }
}

impl PatchHot {
    /// Packs a patch whose frame is `frame`, whose support radii along `t1` and `t2` are
    /// `radii` (`radii.x >= radii.y`) and whose height field over that frame is
    /// `f(u,v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²`.
    pub fn new(origin: Vec3, frame: PackedTangentFrame, radii: Vec2, coefficients: [f32; 6]) -> Self {
        let radius = radii.x;
        let aspect = if radius > 0.0 { (radii.y / radius).clamp(0.0, 1.0) } else { 1.0 };
        let [c0, c1, c2, c3, c4, c5] = coefficients;
        let unit = if radius > 0.0 { radius } else { 1.0 };
        let surface_point = origin + c0 * unpack_normal(frame.word);
        Self {
            origin: surface_point.to_array(),
            radius,
            frame: frame.word,
            aspect_c1: (pack_unorm2x16(Vec2::new(aspect, 0.0)) & 0xffff)
                | (pack_half2x16(Vec2::new(0.0, c1)) & 0xffff_0000),
            coefficients: [
                pack_half2x16(Vec2::new(c2, c3 * unit)),
                pack_half2x16(Vec2::new(c4 * unit, c5 * unit)),
            ],
        }
    }

    /// A patch with a round support of `radius`, in the stored frame nearest to `(tangent,
    /// normal)`.
    pub fn isotropic(origin: Vec3, tangent: Vec3, normal: Vec3, coefficients: [f32; 6], radius: f32) -> Self {
        Self::new(origin, PackedTangentFrame::new(normal, tangent), Vec2::splat(radius), coefficients)
    }

    /// The patch's origin: the fitted surface over its point.
    pub fn origin(&self) -> Vec3 {
        Vec3::from_array(self.origin)
    }

    /// `d_u`, the larger support radius: the patch lies within it of its origin.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// The normal `n_i` as stored.
    pub fn normal(&self) -> Vec3 {
        unpack_normal(self.frame)
    }

    /// The stored frame.
    pub fn frame(&self) -> PackedTangentFrame {
        PackedTangentFrame { word: self.frame }
    }

    /// The patch as the maths works on it.
    pub fn decode(&self) -> Patch {
        let aspect = unpack_unorm2x16(self.aspect_c1).x;
        let c1 = unpack_half2x16(self.aspect_c1).y;
        let unit = if self.radius > 0.0 { self.radius } else { 1.0 };
        let [c2_c3, c4_c5] = self.coefficients.map(unpack_half2x16);
        Patch {
            origin: self.origin(),
            frame: self.frame().decode(),
            radii: Vec2::new(self.radius, self.radius * aspect),
            coefficients: [0.0, c1, c2_c3.x, c2_c3.y / unit, c4_c5.x / unit, c4_c5.y / unit],
        }
    }
}

/// A patch decoded from its `PatchHot`: the frame, support and height field of METHOD.md §2.
/// Twin of `Patch` in `shaders/patch_frame.glsl`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch {
    pub origin: Vec3,
    pub frame: TangentFrame,
    /// `(d_u, d_v)`: the support's radii along `t1` and `t2`.
    pub radii: Vec2,
    /// `c0 .. c5` of `f(u,v) = c0 + c1 u + c2 v + c3 u² + c4 uv + c5 v²`.
    pub coefficients: [f32; 6],
}

impl Patch {
    /// World position to local `(u, v, w)`.
    pub fn to_local(&self, world: Vec3) -> Vec3 {
        self.frame.to_local(world - self.origin)
    }

    /// Local `(u, v, w)` to world position.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.origin + self.frame.to_world(local)
    }

    /// A world direction to local axes.
    pub fn direction_to_local(&self, world: Vec3) -> Vec3 {
        self.frame.to_local(world)
    }

    /// A local direction to world axes.
    pub fn direction_to_world(&self, local: Vec3) -> Vec3 {
        self.frame.to_world(local)
    }

    /// Whether local `(u, v)` lies over the support ellipse: `(u / d_u)² + (v / d_v)² <= 1`,
    /// multiplied out, so that the intersection test, which asks it on every call, divides
    /// nothing.
    pub fn supports(&self, uv: Vec2) -> bool {
        let squared = self.radii * self.radii;
        uv.x * uv.x * squared.y + uv.y * uv.y * squared.x <= squared.x * squared.y
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

    /// The cube of half-size `half` around `center` (the paper's box, METHOD.md §2.4).
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
        assert_eq!(std::mem::size_of::<PatchHot>(), 32);
        assert_eq!(std::mem::size_of::<PatchCold>(), 12);
        assert_eq!(std::mem::size_of::<Aabb>(), 24);
    }

    #[test]
    fn local_and_world_round_trip() {
        let n = Vec3::new(1.0, 2.0, 2.0).normalize();
        let t = n.any_orthonormal_vector();
        let patch = PatchHot::isotropic(Vec3::new(1.0, -2.0, 0.5), t, n, [0.0; 6], 0.1).decode();
        let p = Vec3::new(0.3, 0.7, -1.1);
        assert!((patch.to_world(patch.to_local(p)) - p).length() < 1e-5);
        assert!(patch.frame.t1.cross(patch.frame.t2).dot(n) > 0.999);
    }

    #[test]
    fn a_packed_patch_decodes_to_its_support_and_coefficients() {
        let n = Vec3::new(-0.2, 0.9, 0.1).normalize();
        let frame = PackedTangentFrame::new(n, n.any_orthonormal_vector());
        let coefficients = [0.001, 0.2, -0.1, 30.0, -12.0, 5.0];
        let patch =
            PatchHot::new(Vec3::new(4.0, 5.0, 6.0), frame, Vec2::new(0.02, 0.005), coefficients).decode();
        assert_eq!(patch.frame, frame.decode());
        assert!((patch.radii - Vec2::new(0.02, 0.005)).abs().max_element() < 1e-7);
        // c0 moves the origin along the normal; the height field keeps the rest.
        assert!((patch.origin - (Vec3::new(4.0, 5.0, 6.0) + 0.001 * patch.frame.n)).length() < 1e-6);
        assert_eq!(patch.coefficients[0], 0.0);
        for (decoded, wanted) in patch.coefficients.iter().zip(coefficients).skip(1) {
            assert!((decoded - wanted).abs() <= wanted.abs() / 1024.0, "{decoded} vs {wanted}");
        }
        assert!(patch.supports(Vec2::new(0.019, 0.0)) && !patch.supports(Vec2::new(0.0, 0.006)));
    }

    #[test]
    fn folding_c0_into_the_origin_keeps_the_surface() {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let frame = PackedTangentFrame::new(n, n.any_orthonormal_vector());
        let (origin, coefficients) = (Vec3::new(1.0, 2.0, 3.0), [0.004, 0.1, -0.2, 3.0, 1.0, -2.0]);
        let stored = PatchHot::new(origin, frame, Vec2::splat(0.05), coefficients).decode();
        let decoded = frame.decode();
        for (u, v) in [(0.0, 0.0), (0.03, -0.01), (-0.02, 0.04)] {
            let [c0, c1, c2, c3, c4, c5] = coefficients;
            let w = c0 + c1 * u + c2 * v + c3 * u * u + c4 * u * v + c5 * v * v;
            let fitted = origin + decoded.to_world(Vec3::new(u, v, w));
            let [_, d1, d2, d3, d4, d5] = stored.coefficients;
            let h = d1 * u + d2 * v + d3 * u * u + d4 * u * v + d5 * v * v;
            assert!((stored.to_world(Vec3::new(u, v, h)) - fitted).length() < 2e-5, "at ({u}, {v})");
        }
    }
}
