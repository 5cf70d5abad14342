//! Linear colour to display bytes. Twin of `shaders/srgb_encode.glsl`: the GPU's display
//! output and every PNG the CPU writes encode with the same curve and rounding.

use glam::Vec3;

/// Encodes a linear value with the sRGB transfer function (IEC 61966-2-1) to 8 bits, after
/// clamping to [0, 1]. NaN becomes 0.
pub fn srgb_encode(linear: f32) -> u8 {
    let linear = if linear.is_nan() { 0.0 } else { linear.clamp(0.0, 1.0) };
    let encoded = if linear <= 0.003_130_8 { 12.92 * linear } else { 1.055 * linear.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round() as u8
}

/// A linear colour as one opaque sRGB8 RGBA pixel, red in the low byte (the byte order of
/// an RGBA8 image in memory).
pub fn srgb_encode_rgba8(linear: Vec3) -> u32 {
    let [r, g, b] = linear.to_array().map(|c| u32::from(srgb_encode(c)));
    r | (g << 8) | (b << 16) | (0xff << 24)
}

/// The same pixel with blue in the low byte (the byte order of a B8G8R8A8 image, the
/// swapchain format many window systems offer).
pub fn srgb_encode_bgra8(linear: Vec3) -> u32 {
    srgb_encode_rgba8(Vec3::new(linear.z, linear.y, linear.x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_matches_the_standard_curve() {
        assert_eq!(srgb_encode(0.0), 0);
        assert_eq!(srgb_encode(1.0), 255);
        assert_eq!(srgb_encode(0.5), 188); // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
        assert_eq!(srgb_encode(0.002), 7); // linear segment: 12.92 * 0.002 * 255 = 6.59
        assert_eq!(srgb_encode(0.2159), 128); // the inverse curve of 128/255
    }

    #[test]
    fn out_of_range_and_nan_are_clamped() {
        assert_eq!(srgb_encode(-3.0), 0);
        assert_eq!(srgb_encode(7.0), 255);
        assert_eq!(srgb_encode(f32::NAN), 0);
        assert_eq!(srgb_encode(f32::INFINITY), 255);
    }

    #[test]
    fn rgba8_packs_red_in_the_low_byte_and_is_opaque() {
        let packed = srgb_encode_rgba8(Vec3::new(1.0, 0.5, 0.0));
        assert_eq!(packed.to_le_bytes(), [255, 188, 0, 255]);
    }

    #[test]
    fn bgra8_packs_blue_in_the_low_byte_and_is_opaque() {
        let packed = srgb_encode_bgra8(Vec3::new(1.0, 0.5, 0.0));
        assert_eq!(packed.to_le_bytes(), [0, 188, 255, 255]);
    }
}
