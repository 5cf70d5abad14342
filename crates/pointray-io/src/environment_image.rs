//! Reading an equirectangular environment map: linear RGB radiance from an OpenEXR (`.exr`)
//! or Radiance (`.hdr`) file, twice as wide as tall, every value finite and non-negative.

use std::path::Path;

use crate::linear_image::{LinearImage, check_texels, read_linear_image};
use crate::{IoError, MemoryBudget};

/// What a map takes a texel at its peak, while the scene builds it (after the decode's
/// `DECODE_BYTES_PER_TEXEL`): the texels read (12 bytes), their scaled copy (12), the map's
/// RGBA texels (16), its f64 weights (8) and the f32 distribution over them, which may hold
/// twice its 4 bytes while it grows (8): 56, rounded up.
pub const ENVIRONMENT_BYTES_PER_TEXEL: u64 = 64;

/// The map at `path`, refused before decoding when it is not twice as wide as tall or does not
/// fit in the memory available now.
pub fn read_environment_image(path: &Path) -> Result<LinearImage, IoError> {
    let check = |width, height| {
        check_shape(path, width, height)?;
        check_texels(path, (width, height), ENVIRONMENT_BYTES_PER_TEXEL, MemoryBudget::of_this_machine())
    };
    let image = read_linear_image(path, check)?;
    if let Some(index) = image.pixels.iter().position(|t| !t.is_finite() || t.min_element() < 0.0) {
        let (x, y) = (index as u32 % image.width, index as u32 / image.width);
        return Err(IoError::malformed(
            path,
            format!(
                "texel ({x}, {y}) is {:?}; an environment map's radiance must be finite and >= 0",
                image.pixels[index].to_array()
            ),
        ));
    }
    Ok(image)
}

fn check_shape(path: &Path, width: u32, height: u32) -> Result<(), IoError> {
    if height == 0 || width != 2 * height {
        return Err(IoError::malformed(
            path,
            format!("is {width} x {height}; an equirectangular map is twice as wide as it is tall"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image_output::write_exr_linear;
    use glam::Vec3;

    fn temporary(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new().prefix(name).tempdir().expect("a temporary folder")
    }

    #[test]
    fn an_exr_map_reads_back_as_written() {
        let folder = temporary("environment");
        let path = folder.path().join("sky.exr");
        let texels: Vec<Vec3> = (0..32).map(|i| Vec3::new(i as f32, 0.5, 1e4)).collect();
        write_exr_linear(&path, 8, 4, &texels).expect("written");
        let image = read_environment_image(&path).expect("read");
        assert_eq!((image.width, image.height), (8, 4));
        assert_eq!(image.pixels, texels);
    }

    #[test]
    fn a_map_that_is_not_twice_as_wide_as_tall_is_refused() {
        let folder = temporary("environment");
        let path = folder.path().join("square.exr");
        write_exr_linear(&path, 4, 4, &[Vec3::ONE; 16]).expect("written");
        let message = read_environment_image(&path).expect_err("refused").to_string();
        assert!(message.contains("square.exr") && message.contains("twice as wide"), "{message}");
    }

    #[test]
    fn negative_or_nan_radiance_is_refused_with_its_texel() {
        let folder = temporary("environment");
        let path = folder.path().join("nan.exr");
        let mut texels = vec![Vec3::ONE; 8];
        texels[5] = Vec3::new(1.0, f32::NAN, 0.0);
        write_exr_linear(&path, 4, 2, &texels).expect("written");
        let message = read_environment_image(&path).expect_err("refused").to_string();
        assert!(message.contains("nan.exr") && message.contains("texel (1, 1)"), "{message}");
    }

    #[test]
    fn other_formats_and_broken_files_are_refused() {
        let folder = temporary("environment");
        let png = folder.path().join("sky.png");
        std::fs::write(&png, b"not read").expect("written");
        let message = read_environment_image(&png).expect_err("refused").to_string();
        assert!(message.contains("sky.png") && message.contains(".hdr"), "{message}");
        let truncated = folder.path().join("truncated.exr");
        std::fs::write(&truncated, b"v/1\x01\x02").expect("written");
        let message = read_environment_image(&truncated).expect_err("refused").to_string();
        assert!(message.contains("truncated.exr") && message.contains("not a readable"), "{message}");
    }
}
