//! Primary rays of the pinhole camera, as the rendering contract defines them
//! (docs/ARCHITECTURE.md). Twin of `shaders/camera_ray.glsl`.

use glam::{UVec2, Vec2, Vec3};

use crate::ray::Ray;

/// The R2 low-discrepancy sequence's step (the plastic number's inverses).
const R2_STEP: Vec2 = Vec2::new(0.754_877_7, 0.569_840_3);

/// Where sample `sample` falls inside its pixel, in `[0, 1)²`: the pixel centre for
/// sample 0, then `fract(0.5 + s * R2_STEP)`, so every backend jitters identically.
pub fn sample_jitter(sample: u32) -> Vec2 {
    if sample == 0 {
        return Vec2::splat(0.5);
    }
    let x = Vec2::splat(0.5) + sample as f32 * R2_STEP;
    // `fract_gl` is `x - floor(x)`, GLSL's `fract`.
    x.fract_gl()
}

/// A pinhole camera: what a scene file's `[camera]` gives and both renderers shoot through.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub vertical_fov_degrees: f32,
}

/// The primary ray through `pixel + jitter` of an image of `size` pixels (top row first).
/// The direction is unit length.
pub fn camera_ray(camera: &Camera, size: UVec2, pixel: UVec2, jitter: Vec2) -> Ray {
    let forward = (camera.look_at - camera.position).normalize();
    let right = forward.cross(camera.up).normalize();
    let true_up = right.cross(forward);
    let tan_half = (0.5 * camera.vertical_fov_degrees.to_radians()).tan();
    let size = size.as_vec2();
    let film = pixel.as_vec2() + jitter;
    let ndc = Vec2::new(2.0 * film.x / size.x - 1.0, 1.0 - 2.0 * film.y / size.y);
    let aspect = size.x / size.y;
    let direction = (forward + ndc.x * tan_half * aspect * right + ndc.y * tan_half * true_up).normalize();
    Ray::new(camera.position, direction)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 0.0, 5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            vertical_fov_degrees: 90.0,
        }
    }

    #[test]
    fn sample_zero_is_the_pixel_centre_and_later_samples_stay_inside() {
        assert_eq!(sample_jitter(0), Vec2::splat(0.5));
        for s in 1..1000 {
            let j = sample_jitter(s);
            assert!(j.cmpge(Vec2::ZERO).all() && j.cmplt(Vec2::ONE).all(), "sample {s}: {j}");
        }
        assert_ne!(sample_jitter(1), sample_jitter(2));
    }

    #[test]
    fn the_centre_of_the_image_looks_at_the_target() {
        let ray = camera_ray(&camera(), UVec2::new(2, 2), UVec2::new(1, 1), Vec2::ZERO);
        assert!((ray.direction - Vec3::NEG_Z).length() < 1e-6);
        assert_eq!(ray.origin, Vec3::new(0.0, 0.0, 5.0));
    }

    #[test]
    fn the_top_left_corner_points_up_and_left_at_the_field_of_view() {
        // 90 degrees vertical fov on a square image: the top-left corner is at 45 degrees
        // both ways, so its direction is (-1, 1, -1) normalised.
        let ray = camera_ray(&camera(), UVec2::new(4, 4), UVec2::ZERO, Vec2::ZERO);
        assert!((ray.direction - Vec3::new(-1.0, 1.0, -1.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn wide_images_widen_horizontally_only() {
        let ray = camera_ray(&camera(), UVec2::new(8, 4), UVec2::new(0, 2), Vec2::ZERO);
        // Left edge, middle row: ndc = (-1, 0), horizontal half-extent tan(45) * 2 = 2.
        assert!((ray.direction - Vec3::new(-2.0, 0.0, -1.0).normalize()).length() < 1e-6);
    }
}
