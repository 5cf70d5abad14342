//! Reading linear RGB images: OpenEXR (`.exr`) or Radiance (`.hdr`), as renders and
//! environment maps are stored.

use std::io::BufReader;
use std::path::Path;

use glam::Vec3;
use image::{ImageFormat, ImageReader, Limits};

use crate::{IoError, ensure_readable_file};

/// The widest image read: 16384 texels, 2 GiB of f32 RGBA for a map while it decodes.
pub const MAX_LINEAR_IMAGE_WIDTH: u32 = 16384;

/// Linear RGB, row-major from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// The whole image; `check_size` sees its size before any pixel is decoded.
pub fn read_linear_image(
    path: &Path,
    check_size: impl FnOnce(u32, u32) -> Result<(), IoError>,
) -> Result<LinearImage, IoError> {
    ensure_readable_file(path)?;
    let format = linear_format(path)?;
    // The size comes from the header alone, before anything is decoded.
    let (width, height) = open(path, format)?.into_dimensions().map_err(|e| unreadable(path, format, e))?;
    if width > MAX_LINEAR_IMAGE_WIDTH {
        return Err(IoError::malformed(
            path,
            format!("is {width} x {height}; images up to {MAX_LINEAR_IMAGE_WIDTH} pixels wide are read"),
        ));
    }
    check_size(width, height)?;
    let mut reader = open(path, format)?;
    let mut limits = Limits::no_limits();
    limits.max_image_width = Some(MAX_LINEAR_IMAGE_WIDTH);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| unreadable(path, format, e))?.into_rgb32f();
    let pixels = decoded.pixels().map(|p| Vec3::from(p.0)).collect();
    Ok(LinearImage { width, height, pixels })
}

fn open(path: &Path, format: ImageFormat) -> Result<ImageReader<BufReader<std::fs::File>>, IoError> {
    let file = std::fs::File::open(path).map_err(|e| IoError::os(path, e))?;
    Ok(ImageReader::with_format(BufReader::new(file), format))
}

fn unreadable(path: &Path, format: ImageFormat, error: image::ImageError) -> IoError {
    IoError::malformed(path, format!("not a readable {format:?} image: {error}"))
}

fn linear_format(path: &Path) -> Result<ImageFormat, IoError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("exr") => Ok(ImageFormat::OpenExr),
        Some("hdr") => Ok(ImageFormat::Hdr),
        other => Err(IoError::Unsupported {
            path: path.to_path_buf(),
            what: format!("image format {:?}", other.unwrap_or("(no extension)")),
            supported: ".exr and .hdr (linear RGB)".into(),
        }),
    }
}
