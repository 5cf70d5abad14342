//! A turntable: the camera orbiting its look-at point about its up axis, for the viewer's
//! scripted frames and `render --turntable`. Deterministic, so a test can compute the camera
//! of any frame.

use glam::{Quat, Vec3};

use crate::Camera;

/// The camera of frame `index` (from 0) of `frames`: `start` turned by
/// `arc_degrees * index / frames` about `start.up` through `start.look_at`. A frame that is
/// not turned is `start` itself, so that one frame renders as the scene's camera does.
pub fn orbit_camera(start: &Camera, index: u32, frames: u32, arc_degrees: f32) -> Camera {
    let fraction = if frames == 0 { 0.0 } else { index as f32 / frames as f32 };
    if arc_degrees * fraction == 0.0 {
        // `look_at + (position - look_at)` in f32 moves a camera that sits far from the
        // render space's origin by a rounding step.
        return *start;
    }
    let turn = Quat::from_axis_angle(start.up.normalize_or(Vec3::Y), (arc_degrees * fraction).to_radians());
    Camera { position: start.look_at + turn * (start.position - start.look_at), ..*start }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> Camera {
        Camera {
            position: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            vertical_fov_degrees: 40.0,
        }
    }

    #[test]
    fn frame_zero_is_the_start_and_distance_is_kept() {
        assert_eq!(orbit_camera(&start(), 0, 30, 360.0), start());
        for i in 0..30 {
            let camera = orbit_camera(&start(), i, 30, 360.0);
            assert!((camera.position.distance(camera.look_at) - 5.0).abs() < 1e-4);
            assert!((camera.position.y - 1.0).abs() < 1e-5, "turns about the up axis");
        }
    }

    #[test]
    fn an_unturned_frame_is_the_start_to_the_bit() {
        // Neither the position nor the look-at point survives `l + (p - l)` in f32.
        let start =
            Camera { position: Vec3::new(0.7, 1.1, 5.0), look_at: Vec3::new(-899.3, -0.3, 0.0), ..start() };
        assert_ne!(
            start.look_at + (start.position - start.look_at),
            start.position,
            "the case is a real one"
        );
        assert_eq!(orbit_camera(&start, 0, 1, 360.0), start);
        assert_eq!(orbit_camera(&start, 5, 8, 0.0), start);
    }

    #[test]
    fn a_quarter_of_the_frames_is_a_quarter_turn() {
        let camera = orbit_camera(&start(), 10, 40, 360.0);
        assert!(camera.position.abs_diff_eq(Vec3::new(5.0, 1.0, 0.0), 1e-4), "{:?}", camera.position);
    }
}
