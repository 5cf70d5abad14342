//! The orthonormal tangent frame `(t1, t2, n)` of a patch (SPEC.md §2.5).

use glam::Vec3;

/// A right-handed orthonormal frame with `t2 = n × t1`, matching `PatchHot::tangent_v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    pub t1: Vec3,
    pub t2: Vec3,
    pub n: Vec3,
}

impl TangentFrame {
    /// Builds the frame from a unit normal without any branch on the normal's direction
    /// that could lose precision (Duff et al. 2017, "Building an Orthonormal Basis,
    /// Revisited"): it stays orthonormal for every unit `n`, including ±z.
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let t1 = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        // t2 is computed as n × t1 rather than taken from Duff's second vector so that the
        // handedness is exactly the one the GPU layout reconstructs.
        Self { t1, t2: n.cross(t1), n }
    }

    /// A world offset from the frame's origin to local `(u, v, w)`.
    pub fn to_local(&self, offset: Vec3) -> Vec3 {
        Vec3::new(offset.dot(self.t1), offset.dot(self.t2), offset.dot(self.n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_orthonormal(frame: TangentFrame) {
        for (a, b) in [(frame.t1, frame.t2), (frame.t1, frame.n), (frame.t2, frame.n)] {
            assert!(a.dot(b).abs() < 1e-6, "{frame:?} not orthogonal");
        }
        for axis in [frame.t1, frame.t2, frame.n] {
            assert!((axis.length() - 1.0).abs() < 1e-6, "{frame:?} not unit");
        }
        assert!((frame.t1.cross(frame.t2) - frame.n).length() < 1e-6, "{frame:?} not right-handed");
    }

    #[test]
    fn orthonormal_for_axes_and_near_poles() {
        let normals = [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::X,
            -Vec3::Y,
            -Vec3::Z,
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
            Vec3::new(0.0, 1e-7, 1.0).normalize(),
            Vec3::new(1.0, 2.0, -3.0).normalize(),
        ];
        for n in normals {
            assert_orthonormal(TangentFrame::from_normal(n));
        }
    }

    #[test]
    fn orthonormal_over_a_sphere_of_directions() {
        for i in 0..2000 {
            // A Fibonacci sphere covers every direction evenly.
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / 2000.0;
            let phi = i as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            assert_orthonormal(TangentFrame::from_normal(Vec3::new(r * phi.cos(), r * phi.sin(), z)));
        }
    }
}
