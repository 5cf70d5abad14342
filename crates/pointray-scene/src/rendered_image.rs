//! A rendered image and its arbitrary output variables (AOVs), as every backend returns it.

use glam::Vec3;

/// Row-major, top row first. Per-pixel AOVs come from the first sample's primary ray.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderedImage {
    pub width: u32,
    pub height: u32,
    /// Linear RGB radiance.
    pub color: Vec<Vec3>,
    /// Distance along the primary ray to the first hit; `f32::INFINITY` where it missed.
    pub depth: Vec<f32>,
    /// World-space shading normal at the first hit, facing the camera; zero where it missed.
    pub normal: Vec<Vec3>,
    /// Index of the scene object hit; `RenderedImage::MISS` where it missed.
    pub instance_id: Vec<u32>,
    /// Index of the patch or triangle hit within its object; `RenderedImage::MISS` where it missed.
    pub primitive_id: Vec<u32>,
    /// The surface's base colour (its BSDF's colour) at the first hit, zero where it missed;
    /// from the path integrator, which has it at hand, and `None` from the others.
    pub albedo: Option<Vec<Vec3>>,
}

impl RenderedImage {
    pub const MISS: u32 = u32::MAX;

    pub fn pixel_count(&self) -> usize {
        (self.width * self.height) as usize
    }

    /// Depths into another unit: a scene loaded in a scaled render space (`RenderSpace`) is
    /// rendered in that space's units, and `factor = space.scale` gives the file's.
    pub fn scale_depth(&mut self, factor: f32) {
        self.depth.iter_mut().for_each(|depth| *depth *= factor);
    }

    pub fn hit_mask(&self) -> Vec<bool> {
        self.instance_id.iter().map(|&id| id != Self::MISS).collect()
    }

    /// The PSNR of this image's colours against `other`'s, each channel clamped to `[0, 1]`,
    /// in dB; infinite when they are equal.
    pub fn color_psnr(&self, other: &Self) -> f64 {
        assert_eq!(self.pixel_count(), other.pixel_count(), "images of different sizes");
        let squared: f64 = self
            .color
            .iter()
            .zip(&other.color)
            .map(|(x, y)| {
                let d = x.clamp(Vec3::ZERO, Vec3::ONE) - y.clamp(Vec3::ZERO, Vec3::ONE);
                f64::from(d.length_squared()) / 3.0
            })
            .sum();
        let mean_squared_error = squared / self.pixel_count().max(1) as f64;
        if mean_squared_error == 0.0 { f64::INFINITY } else { -10.0 * mean_squared_error.log10() }
    }
}
