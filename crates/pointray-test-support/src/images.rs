//! How far apart two images are.

/// The largest difference of any byte of two images of the same layout.
pub fn largest_byte_difference(a: &[u8], b: &[u8]) -> u8 {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0)
}

/// The peak signal-to-noise ratio of two 8-bit images of the same layout, in dB; infinite
/// when they are equal.
pub fn psnr_bytes(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    let squared: f64 = a.iter().zip(b).map(|(&x, &y)| (f64::from(x) - f64::from(y)).powi(2)).sum();
    decibels(squared / a.len() as f64, 255.0)
}

/// The largest difference of any colour channel of two images.
#[cfg(feature = "images")]
pub fn largest_color_difference(a: &pointray_scene::RenderedImage, b: &pointray_scene::RenderedImage) -> f32 {
    assert_eq!(a.pixel_count(), b.pixel_count(), "images of different sizes");
    a.color.iter().zip(&b.color).map(|(x, y)| (*x - *y).abs().max_element()).fold(0.0, f32::max)
}

/// The peak signal-to-noise ratio of two images' linear colours, with a peak of 1, in dB.
#[cfg(feature = "images")]
pub fn psnr_colors(a: &pointray_scene::RenderedImage, b: &pointray_scene::RenderedImage) -> f64 {
    assert_eq!(a.pixel_count(), b.pixel_count(), "images of different sizes");
    let squared: f64 = a.color.iter().zip(&b.color).map(|(x, y)| f64::from((*x - *y).length_squared())).sum();
    decibels(squared / (3 * a.pixel_count()) as f64, 1.0)
}

fn decibels(mean_squared_error: f64, peak: f64) -> f64 {
    if mean_squared_error == 0.0 { f64::INFINITY } else { 10.0 * (peak * peak / mean_squared_error).log10() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_images_are_infinitely_close_and_one_step_is_measured() {
        assert_eq!(psnr_bytes(&[1, 2, 3], &[1, 2, 3]), f64::INFINITY);
        assert_eq!(largest_byte_difference(&[1, 2, 3], &[1, 5, 3]), 3);
        // One byte of four off by 255: MSE = 255² / 4, so 10 log10(4) dB.
        let psnr = psnr_bytes(&[0, 0, 0, 0], &[255, 0, 0, 0]);
        assert!((psnr - 10.0 * 4f64.log10()).abs() < 1e-12, "{psnr}");
    }
}
