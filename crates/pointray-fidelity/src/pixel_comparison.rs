//! The pixel-by-pixel comparison of a points image against the mesh image of the same view,
//! kept as counts and error samples so that views can be pooled before the statistics.

use glam::Vec3;
use pointray_scene::RenderedImage;

use crate::FidelityError;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelComparison {
    /// Pixels the mesh covers.
    pub mesh_pixels: u64,
    /// Pixels the mesh covers and the points miss.
    pub hole_pixels: u64,
    /// Holes whose eight neighbours the mesh also covers: seen through the surface, where
    /// the other holes lie on the mesh's silhouette and only move its edge by a pixel.
    pub pinhole_pixels: u64,
    /// Pixels the points cover and the mesh misses.
    pub false_surface_pixels: u64,
    /// `|d_points - d_mesh| / diagonal` at each pixel both hit.
    pub depth_errors: Vec<f32>,
    /// Unsigned angle in degrees between the two normals at each pixel both hit.
    pub normal_errors_degrees: Vec<f32>,
    /// Sum over all pixels and channels of the squared difference of the colours, each
    /// clamped to [0, 1] as a display would.
    pub squared_color_error: f64,
    /// Pixels times channels summed in `squared_color_error`.
    pub color_samples: u64,
    /// The same counts over the mesh pixels a scan's sensor could have seen, when it is known.
    pub seen: Option<SeenCounts>,
}

/// Mesh pixels a sensor could have seen (`SensorVisibility`), and the holes among them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SeenCounts {
    pub mesh_pixels: u64,
    pub hole_pixels: u64,
}

impl PixelComparison {
    /// Compares two images of the same camera; depth errors are divided by `diagonal`.
    pub fn of_images(
        mesh: &RenderedImage,
        points: &RenderedImage,
        diagonal: f32,
    ) -> Result<Self, FidelityError> {
        if (mesh.width, mesh.height) != (points.width, points.height) {
            return Err(FidelityError::ImageSizeMismatch {
                mesh_width: mesh.width,
                mesh_height: mesh.height,
                points_width: points.width,
                points_height: points.height,
            });
        }
        let mut comparison = Self::default();
        for pixel in 0..mesh.pixel_count() {
            comparison.add_pixel(mesh, points, pixel, diagonal);
        }
        Ok(comparison)
    }

    /// Counts the holes among the mesh pixels marked `seen` (one flag a pixel).
    pub fn count_seen(&mut self, points: &RenderedImage, seen: &[bool]) {
        let mut counts = SeenCounts::default();
        for (pixel, _) in seen.iter().enumerate().filter(|(_, seen)| **seen) {
            counts.mesh_pixels += 1;
            counts.hole_pixels += u64::from(points.instance_id[pixel] == RenderedImage::MISS);
        }
        self.seen = Some(counts);
    }

    /// Pools another view's pixels into this one.
    pub fn merge(&mut self, other: PixelComparison) {
        self.mesh_pixels += other.mesh_pixels;
        self.hole_pixels += other.hole_pixels;
        self.pinhole_pixels += other.pinhole_pixels;
        self.false_surface_pixels += other.false_surface_pixels;
        self.depth_errors.extend(other.depth_errors);
        self.normal_errors_degrees.extend(other.normal_errors_degrees);
        self.squared_color_error += other.squared_color_error;
        self.color_samples += other.color_samples;
        self.seen = match (self.seen, other.seen) {
            (Some(a), Some(b)) => Some(SeenCounts {
                mesh_pixels: a.mesh_pixels + b.mesh_pixels,
                hole_pixels: a.hole_pixels + b.hole_pixels,
            }),
            (a, b) => a.or(b),
        };
    }

    fn add_pixel(&mut self, mesh: &RenderedImage, points: &RenderedImage, pixel: usize, diagonal: f32) {
        let mesh_hit = mesh.instance_id[pixel] != RenderedImage::MISS;
        let points_hit = points.instance_id[pixel] != RenderedImage::MISS;
        self.mesh_pixels += u64::from(mesh_hit);
        let hole = mesh_hit && !points_hit;
        self.hole_pixels += u64::from(hole);
        self.pinhole_pixels += u64::from(hole && mesh_covers_around(mesh, pixel));
        self.false_surface_pixels += u64::from(points_hit && !mesh_hit);
        if mesh_hit && points_hit {
            self.depth_errors.push((points.depth[pixel] - mesh.depth[pixel]).abs() / diagonal);
            self.normal_errors_degrees.push(unsigned_angle_degrees(mesh.normal[pixel], points.normal[pixel]));
        }
        let difference =
            mesh.color[pixel].clamp(Vec3::ZERO, Vec3::ONE) - points.color[pixel].clamp(Vec3::ZERO, Vec3::ONE);
        self.squared_color_error += f64::from(difference.length_squared());
        self.color_samples += 3;
    }
}

/// Whether the mesh covers all eight neighbours of `pixel` (pixels past the image's edge count
/// as uncovered).
fn mesh_covers_around(mesh: &RenderedImage, pixel: usize) -> bool {
    let (width, height) = (mesh.width as i64, mesh.height as i64);
    let (x, y) = ((pixel as i64) % width, (pixel as i64) / width);
    (-1..=1).all(|dy| {
        (-1..=1).all(|dx| {
            let (nx, ny) = (x + dx, y + dy);
            (0..width).contains(&nx)
                && (0..height).contains(&ny)
                && mesh.instance_id[(ny * width + nx) as usize] != RenderedImage::MISS
        })
    })
}

/// The angle between two lines (a normal and its flip count as the same); a zero normal is
/// treated as perpendicular to everything, so a broken normal shows as a large error.
pub(crate) fn unsigned_angle_degrees(a: Vec3, b: Vec3) -> f32 {
    let cosine = a.normalize_or_zero().dot(b.normalize_or_zero()).abs().min(1.0);
    cosine.acos().to_degrees()
}
