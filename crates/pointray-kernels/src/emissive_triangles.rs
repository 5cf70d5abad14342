//! Emissive mesh triangles as one light for next-event estimation: a triangle drawn in
//! proportion to its area, a point uniform on it, and the density of that per steradian.
//! Twin of `shaders/emissive_triangles.glsl`. Triangles emit from both sides, as an emissive
//! material does wherever a path meets it.

use glam::{Vec2, Vec3};

use crate::LightSample;
use crate::distribution::{cumulative, sample_cumulative};

/// Vec4 records a triangle takes: its three corners in world space, then its radiance.
pub const EMISSIVE_RECORD_WIDTH: usize = 4;

/// The emissive triangles of a scene, laid out as the GPU reads them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EmissiveTriangles {
    records: Vec<[f32; 4]>,
    /// The triangles' cumulative areas, from 0 to exactly 1 (`count + 1` values).
    distribution: Vec<f32>,
    total_area: f32,
}

impl EmissiveTriangles {
    /// Triangles (world-space corners) with the radiance each emits; those of no area are
    /// left out.
    pub fn new(triangles: impl IntoIterator<Item = ([Vec3; 3], Vec3)>) -> Self {
        let mut records = Vec::new();
        let mut areas = Vec::new();
        for ([a, b, c], radiance) in triangles {
            let area = 0.5 * f64::from((b - a).cross(c - a).length());
            if area > 0.0 && radiance != Vec3::ZERO {
                records.extend([a, b, c, radiance].map(|v| [v.x, v.y, v.z, 0.0]));
                areas.push(area);
            }
        }
        let total_area = areas.iter().sum::<f64>() as f32;
        Self { records, distribution: cumulative(&areas), total_area }
    }

    pub fn count(&self) -> u32 {
        (self.records.len() / EMISSIVE_RECORD_WIDTH) as u32
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    pub fn records(&self) -> &[[f32; 4]] {
        &self.records
    }

    pub fn distribution(&self) -> &[f32] {
        &self.distribution
    }

    pub fn total_area(&self) -> f32 {
        self.total_area
    }

    fn corner(&self, triangle: u32, corner: u32) -> Vec3 {
        let [x, y, z, _] = self.records[triangle as usize * EMISSIVE_RECORD_WIDTH + corner as usize];
        Vec3::new(x, y, z)
    }
}

/// The density per steradian, seen from a point `distance` away, of a point drawn on the
/// triangles where a ray arrives at `cos_theta` to the triangle's normal.
pub fn emissive_pdf(triangles: &EmissiveTriangles, distance: f32, cos_theta: f32) -> f32 {
    let cosine = cos_theta.abs();
    if cosine == 0.0 || triangles.total_area <= 0.0 {
        return 0.0;
    }
    distance * distance / (cosine * triangles.total_area)
}

/// A point on the triangles seen from `position`: `pick` chooses the triangle, `u` the point.
pub fn emissive_sample(triangles: &EmissiveTriangles, pick: f32, u: Vec2, position: Vec3) -> LightSample {
    let none = LightSample { direction: Vec3::Z, distance: 0.0, radiance: Vec3::ZERO, pdf: 0.0 };
    let (triangle, _) = sample_cumulative(&triangles.distribution, pick);
    let (a, b, c) =
        (triangles.corner(triangle, 0), triangles.corner(triangle, 1), triangles.corner(triangle, 2));
    let root = u.x.sqrt();
    let point = a * (1.0 - root) + b * (u.y * root) + c * (root * (1.0 - u.y));
    let offset = point - position;
    let distance2 = offset.length_squared();
    if distance2 <= 0.0 {
        return none;
    }
    let distance = distance2.sqrt();
    let direction = offset / distance;
    let normal = (b - a).cross(c - a).normalize();
    let pdf = emissive_pdf(triangles, distance, normal.dot(direction));
    if pdf <= 0.0 {
        return none;
    }
    LightSample { direction, distance, radiance: triangles.corner(triangle, 3), pdf }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit right triangles of different size making a 1 x 3 rectangle at y = 1.
    fn panel() -> EmissiveTriangles {
        let corners = [Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 3.0)];
        let other = [Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 3.0), Vec3::new(0.0, 1.0, 3.0)];
        EmissiveTriangles::new([
            (corners, Vec3::splat(2.0)),
            (other, Vec3::splat(2.0)),
            ([Vec3::ZERO; 3], Vec3::ONE),
        ])
    }

    #[test]
    fn degenerate_triangles_are_left_out_and_areas_add_up() {
        let panel = panel();
        assert_eq!(panel.count(), 2);
        assert_eq!(panel.distribution(), &[0.0, 0.5, 1.0]);
        assert!((panel.total_area() - 3.0).abs() < 1e-6);
        assert!(EmissiveTriangles::new([]).is_empty());
    }

    #[test]
    fn drawn_points_lie_on_the_panel_with_the_density_of_their_direction() {
        let panel = panel();
        let from = Vec3::new(0.3, 0.0, 0.5);
        for i in 0..400 {
            let (pick, u) = ((i % 20) as f32 / 20.0 + 0.01, Vec2::new((i / 20) as f32 / 20.0 + 0.02, 0.37));
            let drawn = emissive_sample(&panel, pick, u, from);
            let point = from + drawn.direction * drawn.distance;
            assert!(
                (point.y - 1.0).abs() < 1e-5
                    && (0.0..=1.0).contains(&point.x)
                    && (0.0..=3.0).contains(&point.z)
            );
            let expected = emissive_pdf(&panel, drawn.distance, drawn.direction.y);
            assert!((drawn.pdf - expected).abs() <= 1e-5 * expected, "{} against {expected}", drawn.pdf);
            assert_eq!(drawn.radiance, Vec3::splat(2.0));
        }
    }

    #[test]
    fn the_density_integrates_the_panels_solid_angle() {
        // E[1 / pdf] over drawn directions is the solid angle the panel subtends.
        let panel = panel();
        let from = Vec3::new(0.5, 0.0, 1.5);
        let n = 40;
        let stratum = |k: u32| (k as f32 + 0.5) / n as f32;
        let mut sum = 0.0;
        for i in 0..n * n * n {
            let u = Vec2::new(stratum(i / n % n), stratum(i / (n * n)));
            sum += 1.0 / emissive_sample(&panel, stratum(i % n), u, from).pdf;
        }
        let solid_angle = sum / (n * n * n) as f32;
        // A 1 x 3 rectangle 1 above, seen from below its centre: 4 asin(sin a sin b), a and b the half-angles.
        let (a, b) = (0.5f32.atan(), 1.5f32.atan());
        let exact = 4.0 * (a.sin() * b.sin()).asin();
        assert!((solid_angle - exact).abs() < 0.01 * exact, "{solid_angle} against {exact}");
    }
}
