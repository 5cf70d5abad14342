//! Lights. Neither kind falls off with distance, so a light's effect is its
//! `color * intensity` wherever it is visible.

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Point {
        position: Vec3,
        color: Vec3,
        intensity: f32,
    },
    /// `direction` is the way the light travels (from the light toward the scene).
    Directional {
        direction: Vec3,
        color: Vec3,
        intensity: f32,
    },
}
