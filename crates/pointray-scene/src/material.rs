//! Materials: Phong parameters for the Whitted integrator, a BSDF for the path integrator.

use glam::Vec3;
use pointray_kernels::Bsdf;
use pointray_kernels::bsdf::{BSDF_CONDUCTOR, BSDF_DIELECTRIC, BSDF_DIFFUSE, BSDF_PLASTIC};
use serde::Deserialize;

/// The BSDF a material gives the path integrator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceKind {
    /// What the Phong parameters stand for (`Material::bsdf`): Lambert of the diffuse
    /// colour, or with `reflectivity > 0` a glossy plastic of that colour.
    #[default]
    Phong,
    Diffuse,
    Conductor,
    Plastic,
    Dielectric,
}

/// The GGX α of the plastic that a reflective Phong material becomes under path tracing.
pub const PHONG_REFLECTION_ROUGHNESS: f32 = 0.05;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Ambient coefficient (multiplies the diffuse colour).
    pub ambient: f32,
    /// Diffuse colour, linear RGB. For point sets with `use_point_colors`, the point's
    /// colour replaces it. Under path tracing, the BSDF's colour.
    pub diffuse: Vec3,
    /// Specular coefficient.
    pub specular: f32,
    pub shininess: f32,
    /// 0 = no reflection, 1 = a mirror.
    pub reflectivity: f32,
    /// Take the diffuse colour from the patch's cold record instead of `diffuse`: the
    /// file's colours, or, with `color_source = "intensity"`, the ramp's colours that
    /// loading wrote there.
    pub use_point_colors: bool,
    /// The path integrator's BSDF.
    pub surface: SurfaceKind,
    /// GGX α of conductors, plastics and glass (0: smooth glass).
    pub roughness: f32,
    /// Index of refraction of glass and of a plastic's coating.
    pub ior: f32,
    /// Radiance emitted from both sides (path integrator only), linear RGB.
    pub emission: Vec3,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            ambient: 0.1,
            diffuse: Vec3::splat(0.8),
            specular: 0.3,
            shininess: 32.0,
            reflectivity: 0.0,
            use_point_colors: false,
            surface: SurfaceKind::Phong,
            roughness: 0.1,
            ior: 1.5,
            emission: Vec3::ZERO,
        }
    }
}

impl Material {
    /// The BSDF at a hit whose base colour (`diffuse` or the point's colour) is `color`.
    pub fn bsdf(&self, color: Vec3) -> Bsdf {
        let (kind, roughness) = match self.surface {
            SurfaceKind::Phong if self.reflectivity > 0.0 => (BSDF_PLASTIC, PHONG_REFLECTION_ROUGHNESS),
            SurfaceKind::Phong | SurfaceKind::Diffuse => (BSDF_DIFFUSE, self.roughness),
            SurfaceKind::Conductor => (BSDF_CONDUCTOR, self.roughness),
            SurfaceKind::Plastic => (BSDF_PLASTIC, self.roughness),
            SurfaceKind::Dielectric => (BSDF_DIELECTRIC, self.roughness),
        };
        Bsdf { kind, color, roughness, ior: self.ior }
    }
}
