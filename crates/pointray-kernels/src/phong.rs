//! Phong shading, one light at a time, as the rendering contract defines it
//! (docs/ARCHITECTURE.md). Twin of `shaders/phong.glsl`.
//!
//! The colour at a hit is `ambient * C + Σ visible lights phong(...)`; the ambient term
//! is the caller's, being independent of the lights.

use glam::Vec3;

/// What Phong needs of a material once the base colour `C` is chosen (the material's
/// diffuse colour, or the point's colour).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongSurface {
    pub base_color: Vec3,
    pub specular: f32,
    pub shininess: f32,
}

/// One light's contribution: `radiance * (max(N·L, 0) C + specular max(R·V, 0)^shininess)`
/// with `R = reflect(-L, N)`; no specular when `N·L <= 0`.
/// `normal` faces the viewer, `to_viewer` is `-ray.direction`, `to_light` points from the
/// hit to the light; all unit length. `radiance` is the light's `color * intensity`.
pub fn phong(normal: Vec3, to_viewer: Vec3, to_light: Vec3, radiance: Vec3, surface: &PhongSurface) -> Vec3 {
    let n_dot_l = normal.dot(to_light);
    if n_dot_l <= 0.0 {
        return Vec3::ZERO;
    }
    // reflect(-L, N) = -L - 2 (N·-L) N = 2 (N·L) N - L
    let reflected = 2.0 * n_dot_l * normal - to_light;
    let r_dot_v = reflected.dot(to_viewer);
    // Only raise a positive base: GLSL's pow(0, y) is undefined, so both twins skip it.
    let highlight = if r_dot_v > 0.0 { r_dot_v.powf(surface.shininess) } else { 0.0 };
    radiance * (n_dot_l * surface.base_color + Vec3::splat(surface.specular * highlight))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SURFACE: PhongSurface =
        PhongSurface { base_color: Vec3::new(0.5, 0.25, 1.0), specular: 0.5, shininess: 8.0 };

    #[test]
    fn head_on_light_gives_full_diffuse_and_specular() {
        let lit = phong(Vec3::Z, Vec3::Z, Vec3::Z, Vec3::ONE, &SURFACE);
        assert!((lit - (SURFACE.base_color + Vec3::splat(0.5))).length() < 1e-6);
    }

    #[test]
    fn diffuse_follows_the_cosine_and_specular_follows_the_mirror_direction() {
        let to_light = Vec3::new(1.0, 0.0, 1.0).normalize();
        let mirror_viewer = Vec3::new(-1.0, 0.0, 1.0).normalize();
        let lit = phong(Vec3::Z, mirror_viewer, to_light, Vec3::splat(2.0), &SURFACE);
        let expected = 2.0 * (to_light.z * SURFACE.base_color + Vec3::splat(0.5));
        assert!((lit - expected).length() < 1e-5, "{lit} vs {expected}");
        // Viewed from the light's side, R·V = 0: diffuse only.
        let diffuse_only = phong(Vec3::Z, to_light, to_light, Vec3::ONE, &SURFACE);
        let cos = to_light.z;
        let r_dot_v: f32 = (2.0 * cos * Vec3::Z - to_light).dot(to_light);
        let expected = cos * SURFACE.base_color + Vec3::splat(0.5 * r_dot_v.max(0.0).powf(8.0));
        assert!((diffuse_only - expected).length() < 1e-5);
    }

    #[test]
    fn light_behind_the_surface_contributes_nothing() {
        assert_eq!(phong(Vec3::Z, Vec3::Z, Vec3::NEG_Z, Vec3::ONE, &SURFACE), Vec3::ZERO);
        assert_eq!(phong(Vec3::Z, Vec3::Z, Vec3::X, Vec3::ONE, &SURFACE), Vec3::ZERO);
    }
}
