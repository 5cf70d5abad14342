//! Writing rendered images and AOVs: 8-bit sRGB PNG for viewing, linear float EXR for
//! measuring, 16-bit and float single-channel images for depth and ids, and 1-bit masks as
//! 8-bit PNG. Pixels are row-major, top row first; every file is written atomically.

use std::fs::File;
use std::io::{self, BufWriter};
use std::path::Path;

use glam::Vec3;
use image::codecs::openexr::OpenExrEncoder;
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder, ImageResult};

pub use pointray_kernels::srgb_encode;

use crate::{IoError, write_atomically};

/// An 8-bit sRGB PNG of linear RGB pixels.
pub fn write_png_srgb(path: &Path, width: u32, height: u32, linear: &[Vec3]) -> Result<(), IoError> {
    check_size(path, width, height, linear.len())?;
    write_encoded(path, |out| encode_srgb8(out, width, height, linear))
}

/// The bytes `write_png_srgb` would write, in memory.
pub fn encode_png_srgb(width: u32, height: u32, linear: &[Vec3]) -> Result<Vec<u8>, IoError> {
    let name = Path::new("(image in memory)");
    check_size(name, width, height, linear.len())?;
    let mut bytes = Vec::new();
    encode_srgb8(&mut bytes, width, height, linear).map_err(|e| IoError::unwritable(name, e.to_string()))?;
    Ok(bytes)
}

fn encode_srgb8(out: impl io::Write, width: u32, height: u32, linear: &[Vec3]) -> ImageResult<()> {
    let bytes: Vec<u8> = linear.iter().flat_map(|p| p.to_array().map(srgb_encode)).collect();
    PngEncoder::new(out).write_image(&bytes, width, height, ExtendedColorType::Rgb8)
}

/// A 32-bit float RGB OpenEXR of linear pixels, unchanged.
pub fn write_exr_linear(path: &Path, width: u32, height: u32, linear: &[Vec3]) -> Result<(), IoError> {
    check_size(path, width, height, linear.len())?;
    let floats: Vec<f32> = linear.iter().flat_map(|p| p.to_array()).collect();
    write_exr_rgb(path, width, height, &floats)
}

/// A single-channel float AOV (depth in world units, ids as floats) as a 32-bit float EXR.
/// The value is stored in R, G and B alike, since the EXR encoder writes only RGB(A).
pub fn write_exr_gray(path: &Path, width: u32, height: u32, values: &[f32]) -> Result<(), IoError> {
    check_size(path, width, height, values.len())?;
    let floats: Vec<f32> = values.iter().flat_map(|&v| [v; 3]).collect();
    write_exr_rgb(path, width, height, &floats)
}

/// A 16-bit grayscale PNG; the caller chooses the mapping of its quantity onto 0..=65535.
pub fn write_png_gray16(path: &Path, width: u32, height: u32, values: &[u16]) -> Result<(), IoError> {
    check_size(path, width, height, values.len())?;
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_ne_bytes()).collect();
    write_encoded(path, |out| PngEncoder::new(out).write_image(&bytes, width, height, ExtendedColorType::L16))
}

/// A mask (for example the hit mask) as an 8-bit grayscale PNG: 255 where set, 0 elsewhere.
pub fn write_png_mask(path: &Path, width: u32, height: u32, mask: &[bool]) -> Result<(), IoError> {
    check_size(path, width, height, mask.len())?;
    let bytes: Vec<u8> = mask.iter().map(|&set| if set { u8::MAX } else { 0 }).collect();
    write_encoded(path, |out| PngEncoder::new(out).write_image(&bytes, width, height, ExtendedColorType::L8))
}

fn write_exr_rgb(path: &Path, width: u32, height: u32, floats: &[f32]) -> Result<(), IoError> {
    let bytes: Vec<u8> = floats.iter().flat_map(|v| v.to_ne_bytes()).collect();
    write_encoded(path, |out| {
        OpenExrEncoder::new(out).write_image(&bytes, width, height, ExtendedColorType::Rgb32F)
    })
}

fn write_encoded(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> ImageResult<()>,
) -> Result<(), IoError> {
    write_atomically(path, |out| encode(out).map_err(io::Error::other))
}

fn check_size(path: &Path, width: u32, height: u32, pixels: usize) -> Result<(), IoError> {
    if width == 0 || height == 0 {
        return Err(IoError::unwritable(path, format!("an image of {width}x{height} pixels is empty")));
    }
    if u64::from(width) * u64::from(height) != pixels as u64 {
        return Err(IoError::unwritable(
            path,
            format!("{pixels} pixels do not make a {width}x{height} image"),
        ));
    }
    Ok(())
}
