//! How far a render is from a reference of the same view (a converged render, or another
//! renderer's): the measures of a path tracer's convergence, over linear RGB.

use glam::Vec3;

/// Dark pixels' relative error is measured against this, so that noise on black does not
/// dominate (as in the comparison with Mitsuba).
pub const DARK_FLOOR: f64 = 0.05;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageDifference {
    /// The root mean square of the channels' differences.
    pub rmse: f64,
    /// The mean over pixels and channels of |a - b| / (b + DARK_FLOOR).
    pub mean_relative_error: f64,
    /// `10 log10(peak² / mse)`, with the reference's largest channel as the peak.
    pub psnr_db: f64,
    /// The image's mean over its reference's (1 when no energy is lost or gained).
    pub energy_ratio: f64,
    /// Pixels with a NaN or infinite channel in the image.
    pub non_finite: usize,
}

impl ImageDifference {
    /// `image` against `reference`, pixel by pixel; the two are the same size.
    pub fn of(image: &[Vec3], reference: &[Vec3]) -> Self {
        assert_eq!(image.len(), reference.len(), "images of one size");
        let (mut squares, mut relative, mut sum, mut reference_sum, mut peak) = (0.0, 0.0, 0.0, 0.0, 0.0f64);
        let mut non_finite = 0;
        for (a, b) in image.iter().zip(reference) {
            if !a.is_finite() {
                non_finite += 1;
                continue;
            }
            for (x, y) in a.to_array().into_iter().zip(b.to_array()) {
                let (x, y) = (f64::from(x), f64::from(y));
                squares += (x - y) * (x - y);
                relative += (x - y).abs() / (y.abs() + DARK_FLOOR);
                sum += x;
                reference_sum += y;
                peak = peak.max(y);
            }
        }
        let channels = (3 * (image.len() - non_finite)).max(1) as f64;
        let mse = squares / channels;
        Self {
            rmse: mse.sqrt(),
            mean_relative_error: relative / channels,
            psnr_db: 10.0 * (peak * peak / mse).log10(),
            energy_ratio: sum / reference_sum,
            non_finite,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_image_equals_itself_and_noise_is_measured() {
        let reference = vec![Vec3::new(1.0, 0.5, 0.0); 4];
        let same = ImageDifference::of(&reference, &reference);
        assert_eq!((same.rmse, same.mean_relative_error, same.energy_ratio), (0.0, 0.0, 1.0));
        assert!(same.psnr_db.is_infinite());
        let brighter: Vec<Vec3> = reference.iter().map(|&p| p + Vec3::splat(0.1)).collect();
        let difference = ImageDifference::of(&brighter, &reference);
        assert!((difference.rmse - 0.1).abs() < 1e-6);
        assert!((difference.psnr_db - 20.0).abs() < 1e-4, "{}", difference.psnr_db);
        assert!((difference.energy_ratio - 1.8 / 1.5).abs() < 1e-6);
        let expected = (0.1 / 1.05 + 0.1 / 0.55 + 0.1 / 0.05) / 3.0;
        assert!((difference.mean_relative_error - expected).abs() < 1e-6);
    }

    #[test]
    fn non_finite_pixels_are_counted_not_averaged() {
        let reference = vec![Vec3::ONE; 3];
        let image = vec![Vec3::ONE, Vec3::new(f32::NAN, 1.0, 1.0), Vec3::ONE];
        let difference = ImageDifference::of(&image, &reference);
        assert_eq!((difference.non_finite, difference.rmse), (1, 0.0));
    }
}
