//! Phong at a hit with one shadow ray per light (the rendering contract).

use glam::Vec3;
use pointray_kernels::{PhongSurface, Ray, phong};
use pointray_scene::light::WhittedLight;
use pointray_scene::{Light, Material, RenderSettings};

use crate::ray_counts::RayCounts;
use crate::renderer::CpuRenderer;

/// A surface point ready to shade, in world space.
pub struct ShadingPoint {
    pub position: Vec3,
    /// Facing the viewer, unit length.
    pub normal: Vec3,
    /// `-ray.direction`.
    pub to_viewer: Vec3,
    /// The material's diffuse colour, or the point's colour.
    pub base_color: Vec3,
    /// Secondary rays leaving this point ignore hits closer than this (`self_clearance`).
    pub clearance: f32,
}

impl CpuRenderer {
    /// `ambient * C + Σ visible lights phong(...)`.
    pub(crate) fn shade(
        &self,
        point: &ShadingPoint,
        material: &Material,
        settings: &RenderSettings,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let surface = PhongSurface {
            base_color: point.base_color,
            specular: material.specular,
            shininess: material.shininess,
        };
        let shadow_origin = point.position + point.normal * self.ray_epsilon;
        let mut color = material.ambient * point.base_color;
        for light in &self.scene.lights {
            let (to_light, distance, radiance) = toward_light(light, point.position);
            // Lights behind the surface add nothing, so their shadow rays are not traced.
            if point.normal.dot(to_light) <= 0.0 {
                continue;
            }
            if settings.shadows {
                counts.shadow += 1;
                if self.occluded(&Ray::new(shadow_origin, to_light), point.clearance, distance, settings) {
                    continue;
                }
            }
            color += phong(point.normal, point.to_viewer, to_light, radiance, &surface);
        }
        color
    }
}

/// Unit direction to the light, how far along it the light is, and its `color * intensity`.
/// Area lights shine from their centres (`Light::as_whitted`).
fn toward_light(light: &Light, position: Vec3) -> (Vec3, f32, Vec3) {
    match light.as_whitted() {
        WhittedLight::Point { position: light_position, color, intensity } => {
            let offset = light_position - position;
            (offset.normalize_or_zero(), offset.length(), color * intensity)
        }
        WhittedLight::Directional { direction, color, intensity } => {
            (-direction.normalize_or_zero(), f32::INFINITY, color * intensity)
        }
    }
}
