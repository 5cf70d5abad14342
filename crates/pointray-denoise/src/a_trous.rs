//! The filter: five passes of a 5x5 B3-spline kernel whose taps lie 1, 2, 4, 8 and 16 pixels
//! apart, each tap weighed by the edge stops. It filters the irradiance (the colour divided
//! by the albedo, where the path integrator gives one) so that textures stay sharp, and puts
//! the albedo back at the end. The noise each pixel holds is first estimated from its
//! neighbours on the same object, then carried through the passes (each tap's weight squared)
//! to scale the colour stop. Pixels that missed the scene are left as they are.

use glam::Vec3;
use pointray_scene::RenderedImage;
use rayon::prelude::*;

use crate::edge_stops::{Guide, Sigmas, color_weight, compressed_luminance, geometry_weight};

const KERNEL: [f32; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];
/// An albedo darker than this is not divided out (it would amplify noise).
const ALBEDO_FLOOR: f32 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseSettings {
    /// Passes, each with twice the last's tap spacing.
    pub passes: u32,
    /// How many standard deviations of a pixel's noise its neighbours' luminance may differ
    /// by and still be averaged.
    pub luminance_sigma: f32,
    /// The power of the normals' cosine.
    pub normal_power: i32,
    /// How far apart two depths may be, as a fraction of the pixel's own depth.
    pub relative_depth_sigma: f32,
}

impl Default for DenoiseSettings {
    fn default() -> Self {
        Self { passes: 5, luminance_sigma: 4.0, normal_power: 64, relative_depth_sigma: 0.02 }
    }
}

/// A pixel's value as it is filtered: the irradiance and the variance of its compressed
/// luminance.
#[derive(Clone, Copy, Debug)]
struct Sample {
    irradiance: Vec3,
    variance: f32,
}

/// The image with its colour filtered; the AOVs are kept.
pub fn denoise(image: &RenderedImage, settings: &DenoiseSettings) -> RenderedImage {
    let albedo = image.albedo.as_deref();
    let albedo_at = |i: usize| albedo.map_or(Vec3::ONE, |albedo| albedo[i].max(Vec3::splat(ALBEDO_FLOOR)));
    let guides: Vec<Guide> = (0..image.pixel_count())
        .map(|i| Guide { instance: image.instance_id[i], depth: image.depth[i], normal: image.normal[i] })
        .collect();
    let irradiance: Vec<Vec3> = image.color.iter().enumerate().map(|(i, &c)| c / albedo_at(i)).collect();
    let mut samples = estimate_noise(image.width, image.height, &irradiance, &guides);
    let sigmas = Sigmas {
        luminance: settings.luminance_sigma,
        normal_power: settings.normal_power,
        relative_depth: settings.relative_depth_sigma,
    };
    for pass in 0..settings.passes {
        samples = filter_pass(image.width, image.height, &samples, &guides, 1 << pass, &sigmas);
    }
    let color = samples
        .iter()
        .enumerate()
        .map(|(i, sample)| {
            if image.instance_id[i] == RenderedImage::MISS {
                image.color[i]
            } else {
                sample.irradiance * albedo_at(i)
            }
        })
        .collect();
    RenderedImage { color, ..image.clone() }
}

/// The variance of each pixel's compressed luminance over the 5x5 pixels around it on the
/// same object.
fn estimate_noise(width: u32, height: u32, irradiance: &[Vec3], guides: &[Guide]) -> Vec<Sample> {
    (0..irradiance.len())
        .into_par_iter()
        .map(|index| {
            let (mut sum, mut squares, mut count) = (0.0, 0.0, 0.0);
            for other in taps(width, height, index, 1) {
                if guides[other.0].instance == guides[index].instance {
                    let luminance = compressed_luminance(irradiance[other.0]);
                    (sum, squares, count) = (sum + luminance, squares + luminance * luminance, count + 1.0);
                }
            }
            let mean = sum / count;
            Sample { irradiance: irradiance[index], variance: (squares / count - mean * mean).max(0.0) }
        })
        .collect()
}

/// The pixels of the 5x5 kernel around `index` whose taps lie `step` apart, inside the image,
/// with their kernel weights.
fn taps(width: u32, height: u32, index: usize, step: i32) -> impl Iterator<Item = (usize, f32)> {
    let (width, height) = (width as i32, height as i32);
    let (x, y) = (index as i32 % width, index as i32 / width);
    (-2..=2).zip(KERNEL).flat_map(move |(dy, ky)| {
        (-2..=2).zip(KERNEL).filter_map(move |(dx, kx)| {
            let (nx, ny) = (x + dx * step, y + dy * step);
            let inside = nx >= 0 && ny >= 0 && nx < width && ny < height;
            inside.then(|| ((ny * width + nx) as usize, kx * ky))
        })
    })
}

fn filter_pass(
    width: u32,
    height: u32,
    samples: &[Sample],
    guides: &[Guide],
    step: i32,
    sigmas: &Sigmas,
) -> Vec<Sample> {
    (0..samples.len())
        .into_par_iter()
        .map(|index| {
            let pixel = &guides[index];
            if pixel.instance == RenderedImage::MISS {
                return samples[index];
            }
            let luminance = compressed_luminance(samples[index].irradiance);
            let deviation = samples[index].variance.sqrt();
            let (mut sum, mut variance, mut total) = (Vec3::ZERO, 0.0, 0.0);
            for (other, kernel) in taps(width, height, index, step) {
                let neighbour = &samples[other];
                let weight = kernel
                    * geometry_weight(pixel, &guides[other], sigmas)
                    * color_weight(
                        luminance,
                        compressed_luminance(neighbour.irradiance),
                        deviation,
                        sigmas.luminance,
                    );
                sum += neighbour.irradiance * weight;
                variance += weight * weight * neighbour.variance;
                total += weight;
            }
            // The centre tap always weighs in, so `total` is positive.
            Sample { irradiance: sum / total, variance: variance / (total * total) }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two objects side by side, each a flat colour with a fixed pseudo-random noise.
    fn two_noisy_halves(noise: f32) -> RenderedImage {
        let (width, height) = (32u32, 16u32);
        let count = (width * height) as usize;
        let left = |i: usize| (i as u32 % width) < width / 2;
        let color = (0..count)
            .map(|i| {
                let jitter = ((i as f32 * 12.9898).sin() * 43_758.547).rem_euclid(1.0) - 0.5;
                let base = if left(i) { Vec3::new(0.8, 0.2, 0.1) } else { Vec3::new(0.1, 0.3, 0.9) };
                base * (1.0 + noise * jitter)
            })
            .collect();
        RenderedImage {
            width,
            height,
            color,
            depth: vec![2.0; count],
            normal: vec![Vec3::Z; count],
            instance_id: (0..count).map(|i| u32::from(!left(i))).collect(),
            primitive_id: vec![0; count],
            albedo: None,
        }
    }

    fn rmse_from_flat(image: &RenderedImage, clean: &RenderedImage) -> f32 {
        let sum: f32 = image.color.iter().zip(&clean.color).map(|(a, b)| (*a - *b).length_squared()).sum();
        (sum / image.color.len() as f32).sqrt()
    }

    #[test]
    fn noise_falls_and_the_outline_between_objects_stays() {
        let clean = two_noisy_halves(0.0);
        let noisy = two_noisy_halves(0.6);
        let denoised = denoise(&noisy, &DenoiseSettings::default());
        let (before, after) = (rmse_from_flat(&noisy, &clean), rmse_from_flat(&denoised, &clean));
        assert!(after < 0.35 * before, "{after} against {before}");
        // No colour crosses the outline: the clean image is left as it is (to rounding).
        let kept = denoise(&clean, &DenoiseSettings::default());
        for (a, b) in kept.color.iter().zip(&clean.color) {
            assert!((*a - *b).abs().max_element() < 1e-6, "{a} against {b}");
        }
        assert_eq!(denoised.instance_id, noisy.instance_id, "the AOVs are kept");
    }

    #[test]
    fn texture_in_the_albedo_is_kept_and_misses_are_untouched() {
        let mut image = two_noisy_halves(0.0);
        let stripes: Vec<Vec3> = (0..image.pixel_count())
            .map(|i| if i % 2 == 0 { Vec3::splat(0.9) } else { Vec3::splat(0.1) })
            .collect();
        image.color = stripes.iter().map(|&a| a * 0.7).collect();
        image.albedo = Some(stripes);
        image.instance_id[0] = RenderedImage::MISS;
        image.color[0] = Vec3::new(5.0, 0.0, 0.0);
        let denoised = denoise(&image, &DenoiseSettings::default());
        for (a, b) in denoised.color.iter().zip(&image.color).skip(1) {
            assert!((*a - *b).abs().max_element() < 1e-5, "{a} against {b}");
        }
        assert_eq!(denoised.color[0], image.color[0]);
    }
}
