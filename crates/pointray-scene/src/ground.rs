//! The built-in ground: a square of two triangles in a plane y = height, facing +Y.

use glam::Vec3;
use pointray_io::TriangleMesh;
use pointray_kernels::Aabb;

use crate::bounds;

/// An automatic ground reaches this many times the other objects' diagonal across, so that
/// shadows and reflections land on it from any sensible light or camera.
pub const AUTO_SIZE_FACTOR: f32 = 4.0;

/// The edge length of a ground with no size when there is nothing else to measure.
pub const FALLBACK_SIZE: f32 = 10.0;

/// Where the ground goes, in world coordinates before the object's own transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundPlacement {
    pub height: f32,
    /// Centre of the square in the XZ plane.
    pub center_xz: [f32; 2],
    pub size: f32,
}

impl GroundPlacement {
    /// `others` are the bounds of every non-ground object, if any. `auto` puts the plane at
    /// their lowest point; otherwise `height` (default 0) is used. The square is centred under
    /// them and `size` defaults to `AUTO_SIZE_FACTOR` times their diagonal.
    pub fn new(others: Option<&Aabb>, auto: bool, height: Option<f32>, size: Option<f32>) -> Self {
        let center = others.map(bounds::center).unwrap_or(Vec3::ZERO);
        let lowest = others.map(|b| b.min[1]).unwrap_or(0.0);
        let measured_size = others.map(|b| bounds::diagonal(b) * AUTO_SIZE_FACTOR).filter(|s| *s > 0.0);
        Self {
            height: if auto { lowest } else { height.unwrap_or(0.0) },
            center_xz: [center.x, center.z],
            size: size.or(measured_size).unwrap_or(FALLBACK_SIZE),
        }
    }

    pub fn mesh(&self) -> TriangleMesh {
        let half = self.size * 0.5;
        let [cx, cz] = self.center_xz;
        let corner = |dx: f32, dz: f32| Vec3::new(cx + dx * half, self.height, cz + dz * half);
        TriangleMesh {
            positions: vec![corner(-1.0, -1.0), corner(-1.0, 1.0), corner(1.0, 1.0), corner(1.0, -1.0)],
            // Wound so that the face normal points to +Y.
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }
}
