//! A pinhole camera.

use glam::Vec3;
use pointray_kernels::PinholeCamera;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub vertical_fov_degrees: f32,
}

impl Camera {
    /// The camera as the shared camera-ray maths takes it.
    pub fn pinhole(&self) -> PinholeCamera {
        PinholeCamera {
            position: self.position,
            look_at: self.look_at,
            up: self.up,
            vertical_fov_degrees: self.vertical_fov_degrees,
        }
    }
}
