//! What a ray that leaves the scene sees, and how the path integrator draws directions
//! toward it: uniformly over the sphere for a colour or a gradient, in proportion to the
//! radiance for a map.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use pointray_kernels::sampling::{UNIFORM_SPHERE_PDF, uniform_sphere};
use pointray_kernels::{
    EnvironmentMap, LightSample, background, environment_pdf, environment_radiance, environment_sample,
};

#[derive(Clone, Debug, PartialEq)]
pub enum Background {
    Solid(Vec3),
    /// Blends from `bottom` (rays pointing down) to `top` (rays pointing up) by the ray
    /// direction's y component.
    Gradient {
        top: Vec3,
        bottom: Vec3,
    },
    /// An equirectangular map: read from an HDR file, or a procedural sun and sky.
    Map(Arc<EnvironmentMap>),
}

impl Background {
    /// The radiance arriving from a unit direction.
    pub fn radiance(&self, direction: Vec3) -> Vec3 {
        match self {
            Self::Solid(color) => background(direction, *color, *color),
            Self::Gradient { top, bottom } => background(direction, *top, *bottom),
            Self::Map(map) => environment_radiance(map, direction),
        }
    }

    /// Whether it lights the scene, and so is one of the emitters that the path integrator
    /// draws from.
    pub fn is_lit(&self) -> bool {
        match self {
            Self::Solid(color) => *color != Vec3::ZERO,
            Self::Gradient { top, bottom } => *top != Vec3::ZERO || *bottom != Vec3::ZERO,
            Self::Map(map) => !map.is_black(),
        }
    }

    /// A direction toward it drawn by two uniform numbers, with its radiance and density.
    pub fn sample(&self, u: Vec2) -> LightSample {
        match self {
            Self::Map(map) => environment_sample(map, u),
            _ => {
                let direction = uniform_sphere(u);
                let radiance = self.radiance(direction);
                LightSample { direction, distance: f32::INFINITY, radiance, pdf: UNIFORM_SPHERE_PDF }
            }
        }
    }

    /// The density with which `sample` draws a unit direction.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        match self {
            Self::Map(map) => environment_pdf(map, direction),
            _ => UNIFORM_SPHERE_PDF,
        }
    }
}
