//! A view's images, for a person to look at what the numbers count: the mesh and the points
//! shaded alike, and where they differ.

use std::path::{Path, PathBuf};

use glam::Vec3;
use pointray_io::image_output::write_png_srgb;
use pointray_scene::RenderedImage;

use crate::FidelityError;

/// Holes where the sensor looked: red.
const HOLE: Vec3 = Vec3::new(0.9, 0.05, 0.05);
/// Holes where the sensor never looked (`seen` says so): dark red.
const UNSEEN_HOLE: Vec3 = Vec3::new(0.25, 0.02, 0.02);
/// Points where the mesh has nothing: blue.
const FALSE_SURFACE: Vec3 = Vec3::new(0.05, 0.2, 0.9);

/// The images of each view, by the name that ends each file's.
const IMAGES: [&str; 3] = ["mesh", "points", "difference"];

/// Whether `path` is named as one of the images `write_view_images` writes (which may then
/// replace it).
pub fn is_view_image(path: &Path) -> bool {
    let name = path.file_name().and_then(|name| name.to_str()).and_then(|name| name.strip_suffix(".png"));
    let Some((index, image)) = name.and_then(|name| name.strip_prefix("view-")?.split_once('-')) else {
        return false;
    };
    index.parse::<usize>().is_ok() && IMAGES.contains(&image)
}

/// Writes `view-<index>-mesh.png`, `-points.png` and `-difference.png` into `folder`; the
/// difference is the points' image greyed, with holes and false surfaces coloured.
pub fn write_view_images(
    folder: &Path,
    index: usize,
    mesh: &RenderedImage,
    points: &RenderedImage,
    seen: Option<&[bool]>,
) -> Result<Vec<PathBuf>, FidelityError> {
    let difference: Vec<Vec3> = (0..mesh.pixel_count())
        .map(|pixel| {
            let mesh_hit = mesh.instance_id[pixel] != RenderedImage::MISS;
            let points_hit = points.instance_id[pixel] != RenderedImage::MISS;
            match (mesh_hit, points_hit) {
                (true, false) if seen.is_none_or(|seen| seen[pixel]) => HOLE,
                (true, false) => UNSEEN_HOLE,
                (false, true) => FALSE_SURFACE,
                _ => {
                    Vec3::splat(points.color[pixel].clamp(Vec3::ZERO, Vec3::ONE).dot(Vec3::splat(1.0 / 3.0)))
                }
            }
        })
        .collect();
    let images = [(IMAGES[0], &mesh.color), (IMAGES[1], &points.color), (IMAGES[2], &difference)];
    let mut written = Vec::with_capacity(images.len());
    for (name, colors) in images {
        let path = folder.join(format!("view-{index}-{name}.png"));
        write_png_srgb(&path, mesh.width, mesh.height, colors)
            .map_err(|source| FidelityError::Image { path: path.clone(), source })?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_images_are_known_by_name() {
        for name in ["view-0-mesh.png", "out/view-12-points.png", "view-3-difference.png"] {
            assert!(is_view_image(Path::new(name)), "{name}");
        }
        for name in ["view-0-mesh.exr", "view-x-mesh.png", "view-0-depth.png", "mesh.png", "view-0.png"] {
            assert!(!is_view_image(Path::new(name)), "{name}");
        }
    }
}
