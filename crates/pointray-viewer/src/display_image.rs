//! A presented display image (sRGB8 RGBA, read back from the GPU) as a `RenderedImage`, so that the
//! direct path's screenshots go through the same writers (PNG, EXR) as the host path's.

use glam::Vec3;
use pointray_scene::RenderedImage;
use pointray_vulkan::DisplayImage;

/// Colour only: the display output has no AOVs (depth infinite, no normals, no ids).
pub(crate) fn image_from_display(image: &DisplayImage) -> RenderedImage {
    let pixels = (image.width * image.height) as usize;
    let color = image
        .rgba8
        .chunks_exact(4)
        .map(|p| Vec3::new(srgb_decode(p[0]), srgb_decode(p[1]), srgb_decode(p[2])))
        .collect();
    RenderedImage {
        width: image.width,
        height: image.height,
        color,
        depth: vec![f32::INFINITY; pixels],
        normal: vec![Vec3::ZERO; pixels],
        instance_id: vec![RenderedImage::MISS; pixels],
        primitive_id: vec![RenderedImage::MISS; pixels],
        albedo: None,
    }
}

/// The inverse of the sRGB transfer function (IEC 61966-2-1) for an 8-bit value.
fn srgb_decode(byte: u8) -> f32 {
    let encoded = f32::from(byte) / 255.0;
    if encoded <= 0.04045 { encoded / 12.92 } else { ((encoded + 0.055) / 1.055).powf(2.4) }
}

#[cfg(test)]
mod tests {
    use pointray_io::image_output::srgb_encode;

    use super::*;

    /// Screenshots write the decoded colour encoded again: every byte must come back as it was.
    #[test]
    fn every_byte_survives_decoding_and_encoding_again() {
        for byte in 0..=255u8 {
            assert_eq!(srgb_encode(srgb_decode(byte)), byte, "byte {byte}");
        }
    }

    #[test]
    fn pixels_keep_their_channels_and_order() {
        let display = DisplayImage { width: 2, height: 1, rgba8: vec![255, 0, 0, 255, 0, 0, 255, 255] };
        let image = image_from_display(&display);
        assert_eq!(image.color, vec![Vec3::X, Vec3::Z]);
        assert_eq!(image.instance_id, vec![RenderedImage::MISS; 2]);
    }
}
