//! A hot record unpacked at upload: the `Patch` that `PatchHot::decode` gives, in floats, so
//! that the intersection shader reads it as it is. Twin of `shaders/unpacked_patch.glsl`.
//!
//! It takes 64 bytes a patch against the packed record's 32, and spares every intersection
//! call the packed record's decoding (an octahedral normal, a tangent basis, a sine and a
//! cosine, half floats). The GPU takes it where a scene fits with it (bench/RESULTS.md,
//! "Unpacked hot records").

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use crate::layout::{Patch, PatchHot};
use crate::tangent_frame::TangentFrame;

/// `Patch` in four 16-byte words. `c0` is 0 in every decoded record, and `t2` is `n × t1`,
/// so neither is stored.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PatchUnpacked {
    /// The origin, and `d_u`.
    pub origin_radius: [f32; 4],
    /// `t1`, and `d_v`.
    pub tangent_minor_radius: [f32; 4],
    /// `n`, and `c1`.
    pub normal_c1: [f32; 4],
    /// `c2, c3, c4, c5`.
    pub c2_c5: [f32; 4],
}

impl From<&PatchHot> for PatchUnpacked {
    fn from(hot: &PatchHot) -> Self {
        let patch = hot.decode();
        let [_, c1, c2, c3, c4, c5] = patch.coefficients;
        let TangentFrame { t1, n, .. } = patch.frame;
        Self {
            origin_radius: patch.origin.extend(patch.radii.x).to_array(),
            tangent_minor_radius: t1.extend(patch.radii.y).to_array(),
            normal_c1: n.extend(c1).to_array(),
            c2_c5: [c2, c3, c4, c5],
        }
    }
}

impl PatchUnpacked {
    /// The patch, as the intersection shader reads it.
    pub fn patch(&self) -> Patch {
        let [ox, oy, oz, radius] = self.origin_radius;
        let [tx, ty, tz, minor_radius] = self.tangent_minor_radius;
        let [nx, ny, nz, c1] = self.normal_c1;
        let [c2, c3, c4, c5] = self.c2_c5;
        let (t1, n) = (Vec3::new(tx, ty, tz), Vec3::new(nx, ny, nz));
        Patch {
            origin: Vec3::new(ox, oy, oz),
            frame: TangentFrame { t1, t2: n.cross(t1), n },
            radii: Vec2::new(radius, minor_radius),
            coefficients: [0.0, c1, c2, c3, c4, c5],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::PackedTangentFrame;

    #[test]
    fn an_unpacked_record_is_the_decoded_patch() {
        let n = Vec3::new(0.3, -0.8, 0.5).normalize();
        let frame = PackedTangentFrame::new(n, n.any_orthonormal_vector());
        let hot = PatchHot::new(
            Vec3::new(1.0, 2.0, 3.0),
            frame,
            Vec2::new(0.04, 0.01),
            [0.002, 0.3, -0.2, 9.0, -4.0, 2.5],
        );
        assert_eq!(std::mem::size_of::<PatchUnpacked>(), 64);
        assert_eq!(PatchUnpacked::from(&hot).patch(), hot.decode());
    }
}
