//! A rendered image as swapchain bytes: sRGB-encoded 8-bit, 4 per pixel, scaled (nearest) to
//! the swapchain's size, since a reduced-resolution or pre-resize image may differ from it.

use pointray_io::image_output::srgb_encode;
use pointray_scene::RenderedImage;

use crate::present::ByteOrder;

pub(crate) fn image_bytes(image: &RenderedImage, width: u32, height: u32, order: ByteOrder) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(width as usize * height as usize * 4);
    for y in 0..height {
        let source_y = nearest(y, height, image.height);
        for x in 0..width {
            let source_x = nearest(x, width, image.width);
            let [r, g, b] =
                image.color[(source_y * image.width + source_x) as usize].to_array().map(srgb_encode);
            let pixel = match order {
                ByteOrder::Bgra => [b, g, r, 255],
                ByteOrder::Rgba => [r, g, b, 255],
            };
            bytes.extend_from_slice(&pixel);
        }
    }
    bytes
}

/// The source index whose pixel covers the centre of target pixel `index`.
fn nearest(index: u32, target: u32, source: u32) -> u32 {
    let scaled = ((index as u64 * 2 + 1) * source as u64) / (target as u64 * 2);
    (scaled as u32).min(source.saturating_sub(1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn image(width: u32, height: u32, color: impl Fn(u32, u32) -> Vec3) -> RenderedImage {
        let n = (width * height) as usize;
        RenderedImage {
            width,
            height,
            color: (0..height)
                .flat_map(|y| (0..width).map(move |x| (x, y)))
                .map(|(x, y)| color(x, y))
                .collect(),
            depth: vec![0.0; n],
            normal: vec![Vec3::ZERO; n],
            instance_id: vec![RenderedImage::MISS; n],
            primitive_id: vec![RenderedImage::MISS; n],
            albedo: None,
        }
    }

    #[test]
    fn same_size_keeps_pixels_and_orders_bytes() {
        let f = image(2, 1, |x, _| if x == 0 { Vec3::new(1.0, 0.0, 0.0) } else { Vec3::new(0.0, 0.0, 1.0) });
        assert_eq!(image_bytes(&f, 2, 1, ByteOrder::Bgra), vec![0, 0, 255, 255, 255, 0, 0, 255]);
        assert_eq!(image_bytes(&f, 2, 1, ByteOrder::Rgba), vec![255, 0, 0, 255, 0, 0, 255, 255]);
    }

    #[test]
    fn upscaling_repeats_each_source_pixel() {
        let f = image(2, 2, |x, y| Vec3::splat(if (x + y) % 2 == 0 { 1.0 } else { 0.0 }));
        let bytes = image_bytes(&f, 4, 4, ByteOrder::Rgba);
        let red = |x: usize, y: usize| bytes[(y * 4 + x) * 4];
        assert_eq!(
            [red(0, 0), red(1, 1), red(2, 0), red(3, 1), red(2, 2), red(0, 3)],
            [255, 255, 0, 0, 255, 0]
        );
    }
}
