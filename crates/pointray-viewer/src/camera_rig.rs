//! The interactive camera: orbit about the look-at point, pan, zoom and WASD flight, kept as
//! yaw, pitch and distance about a target so that orbiting never drifts.

use glam::{Vec2, Vec3};
use pointray_scene::Camera;

/// Radians of orbit per pixel of mouse drag.
const ORBIT_PER_PIXEL: f32 = 0.008;
/// Keeps the view off the poles, where the up vector and view direction would align.
const PITCH_LIMIT: f32 = 1.55;
/// Distance multiplier per wheel line.
const ZOOM_PER_LINE: f32 = 0.9;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRig {
    target: Vec3,
    distance: f32,
    yaw: f32,
    pitch: f32,
    up: Vec3,
    vertical_fov_degrees: f32,
}

impl CameraRig {
    pub fn from_camera(camera: &Camera) -> Self {
        let up = camera.up.normalize_or(Vec3::Y);
        let offset = camera.position - camera.look_at;
        let distance = offset.length().max(1e-6);
        let (right_axis, back_axis) = horizontal_axes(up);
        let height = offset.dot(up) / distance;
        let pitch = height.clamp(-1.0, 1.0).asin().clamp(-PITCH_LIMIT, PITCH_LIMIT);
        let yaw = offset.dot(right_axis).atan2(offset.dot(back_axis));
        Self {
            target: camera.look_at,
            distance,
            yaw,
            pitch,
            up,
            vertical_fov_degrees: camera.vertical_fov_degrees,
        }
    }

    pub fn camera(&self) -> Camera {
        let (right_axis, back_axis) = horizontal_axes(self.up);
        let horizontal = right_axis * self.yaw.sin() + back_axis * self.yaw.cos();
        let offset = (horizontal * self.pitch.cos() + self.up * self.pitch.sin()) * self.distance;
        Camera {
            position: self.target + offset,
            look_at: self.target,
            up: self.up,
            vertical_fov_degrees: self.vertical_fov_degrees,
        }
    }

    /// A drag of `pixels` turns the camera about the target (right drag: camera moves left).
    pub fn orbit(&mut self, pixels: Vec2) {
        self.yaw -= pixels.x * ORBIT_PER_PIXEL;
        self.pitch = (self.pitch + pixels.y * ORBIT_PER_PIXEL).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// A drag of `pixels` in a window `height` pixels high moves the scene with the mouse.
    pub fn pan(&mut self, pixels: Vec2, height: u32) {
        let (right, up) = self.screen_axes();
        let world_per_pixel =
            2.0 * self.distance * (self.vertical_fov_degrees.to_radians() / 2.0).tan() / height.max(1) as f32;
        self.target += (-right * pixels.x + up * pixels.y) * world_per_pixel;
    }

    /// Positive `lines` (wheel forward) move closer.
    pub fn zoom(&mut self, lines: f32) {
        self.distance = (self.distance * ZOOM_PER_LINE.powf(lines)).max(1e-4);
    }

    /// Moves camera and target together by `step` = (right, up, forward) in units of the
    /// distance to the target, so flight speed suits the scene's scale.
    pub fn fly(&mut self, step: Vec3) {
        let (right, up) = self.screen_axes();
        let forward = (self.target - self.camera().position).normalize_or_zero();
        self.target += (right * step.x + up * step.y + forward * step.z) * self.distance;
    }

    fn screen_axes(&self) -> (Vec3, Vec3) {
        let camera = self.camera();
        let forward = (camera.look_at - camera.position).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        (right, right.cross(forward))
    }
}

/// Two unit vectors perpendicular to `up`: "right" and "back" (toward +Z when up is +Y).
fn horizontal_axes(up: Vec3) -> (Vec3, Vec3) {
    let reference = if up.dot(Vec3::Z).abs() < 0.9 { Vec3::Z } else { Vec3::X };
    let back = (reference - up * reference.dot(up)).normalize();
    (up.cross(back), back)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(1.0, 2.0, 4.0),
            look_at: Vec3::new(0.5, 0.5, 0.0),
            up: Vec3::Y,
            vertical_fov_degrees: 40.0,
        }
    }

    #[test]
    fn round_trips_the_camera() {
        let back = CameraRig::from_camera(&camera()).camera();
        assert!(back.position.abs_diff_eq(camera().position, 1e-4), "{:?}", back.position);
        assert_eq!(back.look_at, camera().look_at);
    }

    #[test]
    fn orbit_keeps_distance_and_target_zoom_changes_distance() {
        let mut rig = CameraRig::from_camera(&camera());
        let distance = camera().position.distance(camera().look_at);
        rig.orbit(Vec2::new(120.0, -40.0));
        let moved = rig.camera();
        assert!(!moved.position.abs_diff_eq(camera().position, 1e-3));
        assert!((moved.position.distance(moved.look_at) - distance).abs() < 1e-4);
        rig.zoom(1.0);
        assert!((rig.camera().position.distance(moved.look_at) - distance * ZOOM_PER_LINE).abs() < 1e-4);
    }

    #[test]
    fn pan_and_fly_move_camera_and_target_together() {
        let mut rig = CameraRig::from_camera(&camera());
        rig.pan(Vec2::new(30.0, 10.0), 480);
        rig.fly(Vec3::new(0.1, 0.0, 0.2));
        let moved = rig.camera();
        assert_ne!(moved.look_at, camera().look_at);
        let offset = moved.position - moved.look_at;
        assert!(offset.abs_diff_eq(camera().position - camera().look_at, 1e-4));
    }
}
