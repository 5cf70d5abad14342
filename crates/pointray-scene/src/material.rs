//! Phong materials.

use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Ambient coefficient (multiplies the diffuse colour).
    pub ambient: f32,
    /// Diffuse colour, linear RGB. For point sets with `use_point_colors`, the point's
    /// colour replaces it.
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
        }
    }
}
