//! Lights. Under the Whitted integrator none falls off with distance, so a light's effect is
//! its `color * intensity` wherever it is visible, and an area light shines as a point light
//! at its centre. Under the path integrator (`source`), `color * intensity` is a point
//! light's intensity (falling off with the squared distance, in the scene file's units),
//! a directional light's irradiance and an area light's emitted radiance, as in Mitsuba.

use glam::Vec3;
use pointray_kernels::LightSource;
use pointray_kernels::light_source::{LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_QUAD, LIGHT_SPHERE};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Point {
        position: Vec3,
        color: Vec3,
        intensity: f32,
        /// The render space's scale (file units per render unit, `RenderSpace::scale`): the
        /// intensity is given over the file's distances, so a scene rescaled to render keeps
        /// its brightness.
        space_scale: f32,
    },
    /// `direction` is the way the light travels (from the light toward the scene).
    Directional { direction: Vec3, color: Vec3, intensity: f32 },
    /// A sphere emitting outward from every point of its surface.
    Sphere { center: Vec3, radius: f32, color: Vec3, intensity: f32 },
    /// The parallelogram `corner + a edge_u + b edge_v` (`a`, `b` in [0, 1]), emitting from
    /// the side that `edge_u × edge_v` faces, black and opaque on the other.
    Quad { corner: Vec3, edge_u: Vec3, edge_v: Vec3, color: Vec3, intensity: f32 },
}

/// A light as the Whitted integrator shades with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WhittedLight {
    Point { position: Vec3, color: Vec3, intensity: f32 },
    Directional { direction: Vec3, color: Vec3, intensity: f32 },
}

impl Light {
    /// A point light in a scene at its file's scale.
    pub fn point(position: Vec3, color: Vec3, intensity: f32) -> Self {
        Self::Point { position, color, intensity, space_scale: 1.0 }
    }

    /// The light as the Whitted integrator shades with it: area lights become point lights
    /// at their centres.
    pub fn as_whitted(&self) -> WhittedLight {
        match *self {
            Self::Point { position, color, intensity, .. } => {
                WhittedLight::Point { position, color, intensity }
            }
            Self::Directional { direction, color, intensity } => {
                WhittedLight::Directional { direction, color, intensity }
            }
            Self::Sphere { center, color, intensity, .. } => {
                WhittedLight::Point { position: center, color, intensity }
            }
            Self::Quad { corner, edge_u, edge_v, color, intensity } => {
                WhittedLight::Point { position: corner + 0.5 * (edge_u + edge_v), color, intensity }
            }
        }
    }

    /// The light as the path integrator samples it.
    pub fn source(&self) -> LightSource {
        let none = Vec3::ZERO;
        let (kind, position, edge_u, edge_v, radius, color, intensity) = match *self {
            Self::Point { position, color, intensity, space_scale } => {
                (LIGHT_POINT, position, none, none, 0.0, color, intensity / (space_scale * space_scale))
            }
            Self::Directional { direction, color, intensity } => {
                (LIGHT_DIRECTIONAL, none, direction, none, 0.0, color, intensity)
            }
            Self::Sphere { center, radius, color, intensity } => {
                (LIGHT_SPHERE, center, none, none, radius, color, intensity)
            }
            Self::Quad { corner, edge_u, edge_v, color, intensity } => {
                (LIGHT_QUAD, corner, edge_u, edge_v, 0.0, color, intensity)
            }
        };
        LightSource { kind, position, edge_u, edge_v, radius, radiance: color * intensity }
    }
}
