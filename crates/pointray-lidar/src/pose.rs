//! Where a sensor stands and which way it faces, and the world direction of each of its rays.

use glam::DVec3;

/// The scene's vertical axis, about which sensors turn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// pointray's scene files: the built-in ground is the plane y = height.
    Y,
    /// LiDAR frames (KITTI, nuScenes, LAS) and the procedural street.
    Z,
}

impl UpAxis {
    pub fn vector(self) -> DVec3 {
        match self {
            Self::Y => DVec3::Y,
            Self::Z => DVec3::Z,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Y => "+Y",
            Self::Z => "+Z",
        }
    }
}

/// A station: the sensor's optical centre, and its heading, in degrees counterclockwise
/// (seen from above) from the world's +X axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorPose {
    pub position: DVec3,
    pub yaw_deg: f64,
}

/// The sensor's axes in the world: forward (azimuth 0), left (azimuth 90°) and up.
#[derive(Clone, Copy, Debug)]
pub struct SensorAxes {
    forward: DVec3,
    left: DVec3,
    up: DVec3,
}

impl SensorAxes {
    pub fn new(up_axis: UpAxis, yaw_deg: f64) -> Self {
        let up = up_axis.vector();
        let (sin, cos) = yaw_deg.to_radians().sin_cos();
        let forward = cos * DVec3::X + sin * up.cross(DVec3::X);
        Self { forward, left: up.cross(forward), up }
    }

    /// The unit direction of the ray at `elevation` above the horizontal and `azimuth`
    /// counterclockwise from forward (radians).
    pub fn direction(&self, elevation: f64, azimuth: f64) -> DVec3 {
        let (sin_elevation, cos_elevation) = elevation.sin_cos();
        let (sin_azimuth, cos_azimuth) = azimuth.sin_cos();
        cos_elevation * (cos_azimuth * self.forward + sin_azimuth * self.left) + sin_elevation * self.up
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_are_right_handed_and_turn_counterclockwise_from_above() {
        for up in [UpAxis::Y, UpAxis::Z] {
            let axes = SensorAxes::new(up, 90.0);
            assert!(axes.forward.cross(axes.left).distance(up.vector()) < 1e-12);
            let at_zero = SensorAxes::new(up, 0.0);
            assert!(at_zero.direction(0.0, 0.0).distance(DVec3::X) < 1e-12);
            // A quarter turn of yaw points forward where the unturned sensor's left was.
            assert!(axes.direction(0.0, 0.0).distance(at_zero.left) < 1e-12);
            assert!(axes.direction(std::f64::consts::FRAC_PI_2, 0.0).distance(up.vector()) < 1e-12);
        }
        assert!(SensorAxes::new(UpAxis::Z, 0.0).left.distance(DVec3::Y) < 1e-12);
    }
}
