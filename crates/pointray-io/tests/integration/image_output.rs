//! Images written by `image_output` read back, through the `image` crate, as written.

use glam::Vec3;
use image::{DynamicImage, ImageReader};
use pointray_io::image_output::{
    srgb_encode, write_exr_gray, write_exr_linear, write_png_gray16, write_png_mask, write_png_srgb,
};

const WIDTH: u32 = 5;
const HEIGHT: u32 = 3;

/// Distinct values per pixel, so that transposed or flipped rows would be caught.
fn gradient() -> Vec<Vec3> {
    (0..WIDTH * HEIGHT)
        .map(|i| Vec3::new(i as f32 / 14.0, 1.0 - i as f32 / 14.0, (i % 4) as f32 * 0.9 - 0.5))
        .collect()
}

fn read(path: &std::path::Path) -> DynamicImage {
    ImageReader::open(path).unwrap().with_guessed_format().unwrap().decode().unwrap()
}

#[test]
fn png_srgb_holds_the_encoded_pixels_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("beauty.png");
    let pixels = gradient();
    write_png_srgb(&path, WIDTH, HEIGHT, &pixels).unwrap();
    let DynamicImage::ImageRgb8(image) = read(&path) else { panic!("not an 8-bit RGB PNG") };
    assert_eq!(image.dimensions(), (WIDTH, HEIGHT));
    for (i, pixel) in pixels.iter().enumerate() {
        let (x, y) = (i as u32 % WIDTH, i as u32 / WIDTH);
        assert_eq!(image.get_pixel(x, y).0, pixel.to_array().map(srgb_encode), "pixel ({x}, {y})");
    }
}

#[test]
fn exr_keeps_linear_floats_exactly_even_beyond_one() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("beauty.exr");
    let mut pixels = gradient();
    pixels[7] = Vec3::new(12.5, -0.25, 1e-6);
    write_exr_linear(&path, WIDTH, HEIGHT, &pixels).unwrap();
    let image = read(&path).into_rgb32f();
    assert_eq!(image.dimensions(), (WIDTH, HEIGHT));
    let read_back: Vec<Vec3> = image.pixels().map(|p| Vec3::from_array(p.0)).collect();
    assert_eq!(read_back, pixels);
}

#[test]
fn single_channel_aovs_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let depth: Vec<f32> = (0..WIDTH * HEIGHT).map(|i| i as f32 * 0.37).collect();
    let depth_path = dir.path().join("depth.exr");
    write_exr_gray(&depth_path, WIDTH, HEIGHT, &depth).unwrap();
    let image = read(&depth_path).into_rgb32f();
    assert!(image.pixels().zip(&depth).all(|(p, d)| p.0 == [*d; 3]));

    let ids: Vec<u16> = (0..WIDTH * HEIGHT).map(|i| (i * 4000) as u16).collect();
    let ids_path = dir.path().join("ids.png");
    write_png_gray16(&ids_path, WIDTH, HEIGHT, &ids).unwrap();
    let DynamicImage::ImageLuma16(image) = read(&ids_path) else { panic!("not a 16-bit gray PNG") };
    assert_eq!(image.into_raw(), ids);
}

#[test]
fn masks_are_black_and_white() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mask.png");
    let mask: Vec<bool> = (0..WIDTH * HEIGHT).map(|i| i % 3 == 0).collect();
    write_png_mask(&path, WIDTH, HEIGHT, &mask).unwrap();
    let DynamicImage::ImageLuma8(image) = read(&path) else { panic!("not an 8-bit gray PNG") };
    let expected: Vec<u8> = mask.iter().map(|&m| if m { 255 } else { 0 }).collect();
    assert_eq!(image.into_raw(), expected);
}

#[test]
fn a_pixel_count_that_does_not_fit_the_size_is_refused_without_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wrong.png");
    let error = write_png_srgb(&path, 4, 4, &gradient()).unwrap_err().to_string();
    assert!(error.contains("wrong.png") && error.contains("15 pixels do not make a 4x4 image"), "{error}");
    assert!(write_png_mask(&path, 0, 0, &[]).unwrap_err().to_string().contains("empty"));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
