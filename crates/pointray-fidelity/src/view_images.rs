//! A view's images, for a person to look at what the numbers count: the mesh and the points
//! shaded alike, where they differ, and how far their normals part.

use std::path::{Path, PathBuf};

use glam::Vec3;
use pointray_io::image_output::write_png_srgb;
use pointray_scene::RenderedImage;

use crate::FidelityError;
use crate::pixel_comparison::unsigned_angle_degrees;

/// Holes where the sensor looked: red.
const HOLE: Vec3 = Vec3::new(0.9, 0.05, 0.05);
/// Holes where the sensor never looked (`seen` says so): dark red.
const UNSEEN_HOLE: Vec3 = Vec3::new(0.25, 0.02, 0.02);
/// Points where the mesh has nothing: blue.
const FALSE_SURFACE: Vec3 = Vec3::new(0.05, 0.2, 0.9);

/// The normal error that saturates the normal-error image's ramp, in degrees.
const NORMAL_ERROR_FULL_SCALE: f32 = 30.0;

/// The images of each view, by the name that ends each file's.
const IMAGES: [&str; 4] = ["mesh", "points", "difference", "normal-error"];

/// Whether `path` is named as one of the images `write_view_images` writes (which may then
/// replace it).
pub fn is_view_image(path: &Path) -> bool {
    let name = path.file_name().and_then(|name| name.to_str()).and_then(|name| name.strip_suffix(".png"));
    let Some((index, image)) = name.and_then(|name| name.strip_prefix("view-")?.split_once('-')) else {
        return false;
    };
    index.parse::<usize>().is_ok() && IMAGES.contains(&image)
}

/// Writes `view-<index>-mesh.png`, `-points.png`, `-difference.png` and `-normal-error.png`
/// into `folder`. The difference is the points' image greyed, with holes and false surfaces
/// coloured; the normal error colours each pixel both hit from black (0°) through red (15°) to
/// yellow (30° or more), with holes and false surfaces as in the difference.
pub fn write_view_images(
    folder: &Path,
    index: usize,
    mesh: &RenderedImage,
    points: &RenderedImage,
    seen: Option<&[bool]>,
) -> Result<Vec<PathBuf>, FidelityError> {
    let grey = |pixel: usize| {
        Vec3::splat(points.color[pixel].clamp(Vec3::ZERO, Vec3::ONE).dot(Vec3::splat(1.0 / 3.0)))
    };
    let normal_heat = |pixel: usize| heat(unsigned_angle_degrees(mesh.normal[pixel], points.normal[pixel]));
    let difference = coverage_image(mesh, points, seen, grey);
    let normal_error = coverage_image(mesh, points, seen, normal_heat);
    let images = [
        (IMAGES[0], &mesh.color),
        (IMAGES[1], &points.color),
        (IMAGES[2], &difference),
        (IMAGES[3], &normal_error),
    ];
    let mut written = Vec::with_capacity(images.len());
    for (name, colors) in images {
        let path = folder.join(format!("view-{index}-{name}.png"));
        write_png_srgb(&path, mesh.width, mesh.height, colors)
            .map_err(|source| FidelityError::Image { path: path.clone(), source })?;
        written.push(path);
    }
    Ok(written)
}

/// Holes and false surfaces coloured, and `both_hit`'s colour where the mesh and the points
/// both cover the pixel.
fn coverage_image(
    mesh: &RenderedImage,
    points: &RenderedImage,
    seen: Option<&[bool]>,
    both_hit: impl Fn(usize) -> Vec3,
) -> Vec<Vec3> {
    (0..mesh.pixel_count())
        .map(|pixel| {
            let mesh_hit = mesh.instance_id[pixel] != RenderedImage::MISS;
            let points_hit = points.instance_id[pixel] != RenderedImage::MISS;
            match (mesh_hit, points_hit) {
                (true, false) if seen.is_none_or(|seen| seen[pixel]) => HOLE,
                (true, false) => UNSEEN_HOLE,
                (false, true) => FALSE_SURFACE,
                (true, true) => both_hit(pixel),
                (false, false) => Vec3::ZERO,
            }
        })
        .collect()
}

/// Black at 0°, red at half the full scale, yellow at the full scale and beyond.
fn heat(degrees: f32) -> Vec3 {
    let t = (degrees / NORMAL_ERROR_FULL_SCALE).clamp(0.0, 1.0);
    Vec3::new((2.0 * t).min(1.0), (2.0 * t - 1.0).max(0.0), 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_images_are_known_by_name() {
        for name in
            ["view-0-mesh.png", "out/view-12-points.png", "view-3-difference.png", "view-1-normal-error.png"]
        {
            assert!(is_view_image(Path::new(name)), "{name}");
        }
        for name in ["view-0-mesh.exr", "view-x-mesh.png", "view-0-depth.png", "mesh.png", "view-0.png"] {
            assert!(!is_view_image(Path::new(name)), "{name}");
        }
    }

    #[test]
    fn the_normal_error_ramp_runs_from_black_through_red_to_yellow() {
        assert_eq!(heat(0.0), Vec3::ZERO);
        assert_eq!(heat(NORMAL_ERROR_FULL_SCALE / 2.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(heat(NORMAL_ERROR_FULL_SCALE), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(heat(90.0), heat(NORMAL_ERROR_FULL_SCALE));
    }
}
