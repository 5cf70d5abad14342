//! The mesh's smooth normal field: angle-weighted vertex normals, interpolated across each
//! triangle. The mesh stands for a smooth surface, and its flat facets' normals jump at
//! every edge by as much as the patches' own error, so errors are measured against this.

use glam::Vec3;
use pointray_io::TriangleMesh;
use pointray_kernels::face_forward;
use pointray_scene::{Camera, RenderedImage};

use crate::FidelityError;
use crate::pixel_rays::PixelRays;

pub struct VertexNormals {
    normals: Vec<Vec3>,
}

impl VertexNormals {
    /// Each vertex's normal is the sum of its triangles' unit normals, each weighted by the
    /// triangle's angle at the vertex (Thürmer and Wüthrich): unlike area weights, it does
    /// not change when a neighbouring triangle is split. Degenerate triangles add nothing.
    pub fn angle_weighted(mesh: &TriangleMesh) -> Self {
        let mut normals = vec![Vec3::ZERO; mesh.positions.len()];
        for (triangle, corners) in mesh.triangles.iter().enumerate() {
            let Some(unit) = mesh.face_normal(triangle).try_normalize() else { continue };
            let points = corners.map(|i| mesh.positions[i as usize]);
            for corner in 0..3 {
                let angle = corner_angle(points[corner], points[(corner + 1) % 3], points[(corner + 2) % 3]);
                normals[corners[corner] as usize] += unit * angle;
            }
        }
        Self { normals: normals.into_iter().map(Vec3::normalize_or_zero).collect() }
    }

    pub fn of_vertex(&self, vertex: usize) -> Vec3 {
        self.normals[vertex]
    }

    /// The unit normal at `point` on `triangle`: the vertex normals blended by the point's
    /// barycentric coordinates. Where they cancel (opposite windings meet at a vertex) or the
    /// triangle is degenerate, the triangle's own normal, or zero if it has none.
    pub fn at(&self, mesh: &TriangleMesh, triangle: usize, point: Vec3) -> Vec3 {
        let corners = mesh.triangles[triangle];
        let positions = corners.map(|i| mesh.positions[i as usize]);
        let face = mesh.face_normal(triangle).normalize_or_zero();
        let Some(weights) = barycentric(positions, point) else { return face };
        let blended: Vec3 = corners.iter().zip(weights).map(|(&i, w)| self.normals[i as usize] * w).sum();
        blended.try_normalize().unwrap_or(face)
    }

    /// Replaces the normals of a image of `mesh` alone, seen by `camera`, with the smooth
    /// normals at each pixel's hit, facing the camera. The hit is rebuilt from the pixel's
    /// primary ray (sample 0, as the AOVs are) and its depth, so any backend's image will do.
    pub fn smooth_image(
        &self,
        image: &mut RenderedImage,
        mesh: &TriangleMesh,
        camera: &Camera,
    ) -> Result<(), FidelityError> {
        let rays = PixelRays::new(camera, image);
        for pixel in 0..image.pixel_count() {
            if image.instance_id[pixel] == RenderedImage::MISS {
                continue;
            }
            let triangle = image.primitive_id[pixel];
            if triangle as usize >= mesh.triangles.len() {
                return Err(FidelityError::TriangleOutOfRange { triangle, triangles: mesh.triangles.len() });
            }
            let ray = rays.ray(pixel);
            let normal = self.at(mesh, triangle as usize, ray.at(image.depth[pixel]));
            image.normal[pixel] = face_forward(normal, ray.direction);
        }
        Ok(())
    }
}

/// The interior angle at `apex` between the edges to `b` and `c`.
fn corner_angle(apex: Vec3, b: Vec3, c: Vec3) -> f32 {
    (b - apex).angle_between(c - apex)
}

/// The barycentric weights of `point` projected onto the triangle's plane, clamped into the
/// triangle (a hit reconstructed from a ray and an f32 depth lies a rounding error off it);
/// `None` for a degenerate triangle.
fn barycentric([a, b, c]: [Vec3; 3], point: Vec3) -> Option<[f32; 3]> {
    let (ab, ac, ap) = (b - a, c - a, point - a);
    let (d00, d01, d11) = (ab.dot(ab), ab.dot(ac), ac.dot(ac));
    let (d20, d21) = (ap.dot(ab), ap.dot(ac));
    let denominator = d00 * d11 - d01 * d01;
    if denominator.abs() <= f32::EPSILON * d00 * d11 {
        return None;
    }
    let v = (d11 * d20 - d01 * d21) / denominator;
    let w = (d00 * d21 - d01 * d20) / denominator;
    let weights = [1.0 - v - w, v, w].map(|x| x.max(0.0));
    let sum: f32 = weights.iter().sum();
    (sum > 0.0).then(|| weights.map(|x| x / sum))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tent: two triangles meeting along the z axis at a right angle.
    fn tent() -> TriangleMesh {
        TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::Z, Vec3::new(1.0, -1.0, 0.0), Vec3::new(-1.0, -1.0, 0.0)],
            triangles: vec![[0, 1, 2], [0, 3, 1]],
        }
    }

    #[test]
    fn the_ridge_gets_the_bisector_and_corners_their_own_face() {
        let mesh = tent();
        let normals = VertexNormals::angle_weighted(&mesh);
        let ridge = Vec3::Y;
        assert!(normals.of_vertex(0).distance(ridge) < 1e-6, "{:?}", normals.of_vertex(0));
        assert!(normals.of_vertex(1).distance(ridge) < 1e-6);
        let first_face = mesh.face_normal(0).normalize();
        assert!(normals.of_vertex(2).distance(first_face) < 1e-6);
        // Halfway from the ridge to the far corner the blend is between the two.
        let halfway = normals.at(&mesh, 0, Vec3::new(0.5, -0.5, 0.0));
        assert!(halfway.distance((ridge + first_face).normalize()) < 1e-6, "{halfway:?}");
    }

    #[test]
    fn a_degenerate_triangle_falls_back_to_zero_without_panicking() {
        let mesh =
            TriangleMesh { positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], triangles: vec![[0, 1, 2]] };
        let normals = VertexNormals::angle_weighted(&mesh);
        assert_eq!(normals.at(&mesh, 0, Vec3::X), Vec3::ZERO);
    }
}
