//! Reading linear RGB images: OpenEXR (`.exr`) or Radiance (`.hdr`), as renders and
//! environment maps are stored.

use std::io::BufReader;
use std::path::Path;

use glam::Vec3;
use image::{ImageFormat, ImageReader, Limits};

use crate::{IoError, MemoryBudget, ensure_readable_file};

/// The widest image read: 16384 texels.
pub const MAX_LINEAR_IMAGE_WIDTH: u32 = 16384;

/// What decoding takes at its peak, a texel: the EXR decoder's f32 RGBA and its RGB
/// conversion alive together (16 + 12 bytes); the HDR decoder's RGB and the texels made from
/// it take less (12 + 12).
pub const DECODE_BYTES_PER_TEXEL: u64 = 28;

/// Linear RGB, row-major from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// The whole image; `check_size` sees its size before any pixel is decoded, and so does a
/// check that decoding it fits in the memory available now.
pub fn read_linear_image(
    path: &Path,
    check_size: impl FnOnce(u32, u32) -> Result<(), IoError>,
) -> Result<LinearImage, IoError> {
    read_linear_image_within(path, MemoryBudget::of_this_machine(), check_size)
}

/// `read_linear_image` within `budget` instead of the memory available (the fuzz target's cap).
pub fn read_linear_image_within(
    path: &Path,
    budget: MemoryBudget,
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
    check_texels(path, (width, height), DECODE_BYTES_PER_TEXEL, budget)?;
    let mut reader = open(path, format)?;
    let mut limits = Limits::no_limits();
    limits.max_image_width = Some(MAX_LINEAR_IMAGE_WIDTH);
    // The decoder's own check, should it allocate beyond what the header said.
    limits.max_alloc = Some(budget.bytes);
    reader.limits(limits);
    let decoded = reader.decode().map_err(|e| unreadable(path, format, e))?.into_rgb32f();
    let pixels = decoded.pixels().map(|p| Vec3::from(p.0)).collect();
    Ok(LinearImage { width, height, pixels })
}

/// Refuses an image of `size` texels whose reading (and what follows it) takes more than
/// `budget` at `bytes_each` a texel, naming the file and the size its header gives.
pub fn check_texels(
    path: &Path,
    (width, height): (u32, u32),
    bytes_each: u64,
    budget: MemoryBudget,
) -> Result<(), IoError> {
    let texels = u64::from(width) * u64::from(height);
    budget.check(texels, bytes_each, "texels").map_err(|shortfall| {
        IoError::unusable(path, format!("its header says {width} x {height}: {shortfall}"))
    })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A Radiance header claiming `width` x `height`, with a few bytes of pixels.
    fn hdr_header(path: &Path, width: u32, height: u32) {
        let header = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n");
        std::fs::write(path, [header.as_bytes(), &[0x80; 16]].concat()).unwrap();
    }

    #[test]
    fn a_header_claiming_more_than_memory_holds_is_refused_before_decoding() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.hdr");
        hdr_header(&path, 16384, 1_000_000_000);
        assert!(std::fs::metadata(&path).unwrap().len() < 100);
        let message = read_linear_image(&path, |_, _| Ok(())).unwrap_err().to_string();
        assert!(message.contains("huge.hdr") && message.contains("16384 x 1000000000"), "{message}");
        assert!(message.contains("of memory"), "{message}");
    }

    #[test]
    fn an_image_is_priced_against_the_budget_it_is_given() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("small.hdr");
        hdr_header(&path, 64, 32);
        let budget = MemoryBudget { bytes: 64 * 32 * DECODE_BYTES_PER_TEXEL - 1 };
        let message = read_linear_image_within(&path, budget, |_, _| Ok(())).unwrap_err().to_string();
        assert!(message.contains("small.hdr") && message.contains("2048 texels"), "{message}");
        let enough = MemoryBudget { bytes: 64 * 32 * DECODE_BYTES_PER_TEXEL };
        let message = read_linear_image_within(&path, enough, |_, _| Ok(())).unwrap_err().to_string();
        assert!(message.contains("not a readable"), "priced, then found truncated: {message}");
    }
}
