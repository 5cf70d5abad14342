//! Writing a `RenderedImage`: the colour image by the output's extension (`.png`: 8-bit sRGB, `.exr`:
//! linear float), and on request each AOV as its own file next to it, named after the output:
//!
//! | AOV | file | content |
//! |---|---|---|
//! | depth | `out.depth.exr` | t along the primary ray, world units; +inf where it missed |
//! | normal | `out.normal.exr` | world normal facing the camera, xyz in RGB; 0 where it missed |
//! | instance | `out.instance.exr` | object index as a float; -1 where it missed |
//! | primitive | `out.primitive.exr` | patch or triangle index as a float; -1 where it missed |
//! | mask | `out.mask.png` | 255 where the primary ray hit, 0 elsewhere |
//! | albedo | `out.albedo.exr` | the base colour at the first hit, linear RGB; 0 where it missed (path integrator only) |
//!
//! Ids are stored as 32-bit floats, which hold integers exactly up to 2^24; a image with a
//! larger id is refused rather than written with rounded ids.

use std::path::{Path, PathBuf};

use pointray_io::image_output::{write_exr_gray, write_exr_linear, write_png_mask, write_png_srgb};

use crate::RenderedImage;
use crate::error::SceneError;

/// Which AOVs to write next to the colour image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AovSelection {
    pub depth: bool,
    pub normal: bool,
    pub instance: bool,
    pub primitive: bool,
    pub mask: bool,
    /// Written only where the image has one (`RenderedImage::albedo`).
    pub albedo: bool,
}

impl AovSelection {
    pub const ALL: Self =
        Self { depth: true, normal: true, instance: true, primitive: true, mask: true, albedo: true };
}

/// The largest id a float holds exactly.
const LARGEST_EXACT_FLOAT_ID: u32 = 1 << 24;

/// Writes the colour image to `path` and the selected AOVs next to it; returns every path
/// written, the colour image first.
pub fn write_image(
    image: &RenderedImage,
    path: &Path,
    aovs: &AovSelection,
) -> Result<Vec<PathBuf>, SceneError> {
    image_paths(path, aovs)?;
    check_ids(image, path, aovs)?;
    let (width, height) = (image.width, image.height);
    let written = |path: &Path, result: Result<(), pointray_io::IoError>| {
        result
            .map(|()| path.to_path_buf())
            .map_err(|source| SceneError::ImageOutput { path: path.to_path_buf(), source })
    };
    let color = match extension(path).as_deref() {
        Some("exr") => write_exr_linear(path, width, height, &image.color),
        _ => write_png_srgb(path, width, height, &image.color),
    };
    let mut paths = vec![written(path, color)?];
    if aovs.depth {
        let aov = aov_path(path, "depth.exr");
        paths.push(written(&aov, write_exr_gray(&aov, width, height, &image.depth))?);
    }
    if aovs.normal {
        let aov = aov_path(path, "normal.exr");
        paths.push(written(&aov, write_exr_linear(&aov, width, height, &image.normal))?);
    }
    if aovs.instance {
        let aov = aov_path(path, "instance.exr");
        paths.push(written(&aov, write_exr_gray(&aov, width, height, &ids_as_floats(&image.instance_id)))?);
    }
    if aovs.primitive {
        let aov = aov_path(path, "primitive.exr");
        paths.push(written(&aov, write_exr_gray(&aov, width, height, &ids_as_floats(&image.primitive_id)))?);
    }
    if aovs.mask {
        let aov = aov_path(path, "mask.png");
        paths.push(written(&aov, write_png_mask(&aov, width, height, &image.hit_mask()))?);
    }
    if let (true, Some(albedo)) = (aovs.albedo, &image.albedo) {
        let aov = aov_path(path, "albedo.exr");
        paths.push(written(&aov, write_exr_linear(&aov, width, height, albedo))?);
    }
    Ok(paths)
}

/// Every file `write_image` may write for `path` and `aovs`, the colour image first (the
/// albedo only where the image has one); an error for an image type it cannot write.
/// Nothing is touched.
pub fn image_paths(path: &Path, aovs: &AovSelection) -> Result<Vec<PathBuf>, SceneError> {
    if !matches!(extension(path).as_deref(), Some("png" | "exr")) {
        return Err(SceneError::ImageFormat {
            path: path.to_path_buf(),
            problem: "unsupported image type; use .png (8-bit sRGB) or .exr (linear float)".into(),
        });
    }
    let selected = [
        (aovs.depth, "depth.exr"),
        (aovs.normal, "normal.exr"),
        (aovs.instance, "instance.exr"),
        (aovs.primitive, "primitive.exr"),
        (aovs.mask, "mask.png"),
        (aovs.albedo, "albedo.exr"),
    ];
    let aov_paths =
        selected.into_iter().filter(|(wanted, _)| *wanted).map(|(_, suffix)| aov_path(path, suffix));
    Ok(std::iter::once(path.to_path_buf()).chain(aov_paths).collect())
}

/// Checks, before any loading, that the image's files can be written and that none of them is
/// one of `inputs` (the scene's files, `SceneFile::input_files`); returns them.
pub fn check_image_outputs(
    path: &Path,
    aovs: &AovSelection,
    inputs: &[PathBuf],
) -> Result<Vec<PathBuf>, SceneError> {
    let paths = image_paths(path, aovs)?;
    pointray_io::ensure_outputs_spare_inputs(inputs, &paths)
        .map_err(|source| SceneError::ImageOutput { path: path.to_path_buf(), source })?;
    Ok(paths)
}

/// `out.png` with suffix `depth.exr` gives `out.depth.exr`, in the same folder.
pub fn aov_path(output: &Path, suffix: &str) -> PathBuf {
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    output.with_file_name(format!("{stem}.{suffix}"))
}

fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase())
}

fn ids_as_floats(ids: &[u32]) -> Vec<f32> {
    ids.iter().map(|&id| if id == RenderedImage::MISS { -1.0 } else { id as f32 }).collect()
}

fn check_ids(image: &RenderedImage, path: &Path, aovs: &AovSelection) -> Result<(), SceneError> {
    let selected =
        [(aovs.instance, "instance", &image.instance_id), (aovs.primitive, "primitive", &image.primitive_id)];
    for (_, name, ids) in selected.into_iter().filter(|(wanted, _, _)| *wanted) {
        if let Some(&id) = ids.iter().find(|&&id| id != RenderedImage::MISS && id > LARGEST_EXACT_FLOAT_ID) {
            return Err(SceneError::ImageFormat {
                path: aov_path(path, &format!("{name}.exr")),
                problem: format!("{name} id {id} is too large to store exactly as a float (limit 2^24)"),
            });
        }
    }
    Ok(())
}
