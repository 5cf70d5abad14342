//! Cameras and epsilons derived from a scene's extent.

use glam::Vec3;
use pointray_kernels::Aabb;

use crate::bounds;
use crate::{Camera, Scene};

/// Secondary rays start this fraction of the scene's diagonal off the surface (ARCHITECTURE.md,
/// rendering contract).
const RAY_EPSILON_FRACTION: f32 = 1e-4;

impl Scene {
    /// World box over every object's surface samples (see `bounds`); `None` with no objects.
    pub fn bounds(&self) -> Option<Aabb> {
        self.objects.iter().filter_map(|object| object.world_bounds()).reduce(|a, b| a.union(&b))
    }

    /// The offset for shadow and reflection rays: `1e-4 x` the bounds' diagonal. An empty or
    /// single-point scene uses a diagonal of 1 so that the offset is never zero.
    pub fn ray_epsilon(&self) -> f32 {
        let diagonal = self.bounds().map(|b| bounds::diagonal(&b)).filter(|d| *d > 0.0).unwrap_or(1.0);
        RAY_EPSILON_FRACTION * diagonal
    }

    /// A camera looking at the centre of `bounds` from `direction` (pointing from the target
    /// toward the camera), far enough that the bounds' enclosing sphere fits the view for an
    /// image of the given aspect ratio (width / height). Up is +Y unless the view is straight
    /// along Y.
    pub fn framing_camera(bounds: &Aabb, direction: Vec3, vfov_degrees: f32, aspect: f32) -> Camera {
        let target = bounds::center(bounds);
        let radius = Some(bounds::diagonal(bounds) * 0.5).filter(|r| *r > 0.0).unwrap_or(1.0);
        let direction = direction.try_normalize().unwrap_or(Vec3::Z);
        let half_vertical = (vfov_degrees.to_radians() * 0.5).clamp(1e-3, 1.5);
        let half_horizontal = (half_vertical.tan() * aspect.max(1e-3)).atan();
        let distance = radius / half_vertical.min(half_horizontal).sin();
        let up = if direction.cross(Vec3::Y).length() < 1e-3 { Vec3::NEG_Z } else { Vec3::Y };
        Camera {
            position: target + direction * distance,
            look_at: target,
            up,
            vertical_fov_degrees: vfov_degrees,
        }
    }
}
