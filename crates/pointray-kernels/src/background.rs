//! The colour of a ray that hits nothing. Twin of `shaders/background.glsl`.

use glam::Vec3;

/// The vertical gradient from `bottom` (straight down) to `top` (straight up) by
/// `s = 0.5 (dir.y + 1)`; a solid background is `top == bottom`, which this returns
/// exactly. `direction` is unit length.
pub fn background(direction: Vec3, top: Vec3, bottom: Vec3) -> Vec3 {
    let s = (0.5 * (direction.y + 1.0)).clamp(0.0, 1.0);
    // bottom + (top - bottom) s rather than mix(): exact for a solid colour on every GPU.
    bottom + (top - bottom) * s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gradient_runs_from_bottom_to_top() {
        let (top, bottom) = (Vec3::new(0.2, 0.4, 1.0), Vec3::new(1.0, 1.0, 1.0));
        assert!((background(Vec3::Y, top, bottom) - top).length() < 1e-6);
        assert_eq!(background(Vec3::NEG_Y, top, bottom), bottom);
        assert!((background(Vec3::X, top, bottom) - 0.5 * (top + bottom)).length() < 1e-6);
    }

    #[test]
    fn a_solid_background_is_exact_in_every_direction() {
        let colour = Vec3::new(0.3, 0.7, 0.11);
        for direction in [Vec3::X, Vec3::new(0.3, -0.9, 0.1).normalize(), Vec3::Y] {
            assert_eq!(background(direction, colour, colour), colour);
        }
    }
}
