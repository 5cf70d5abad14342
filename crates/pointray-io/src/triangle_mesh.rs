//! An indexed triangle mesh.

use glam::Vec3;

/// Triangles index `positions`; their winding is kept as the file gives it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// The unnormalised face normal (its length is twice the triangle's area).
    pub fn face_normal(&self, triangle: usize) -> Vec3 {
        let [a, b, c] = self.triangles[triangle].map(|i| self.positions[i as usize]);
        (b - a).cross(c - a)
    }

    /// Appends a polygon as a fan of triangles around its first vertex (exact for convex
    /// polygons, which is what mesh files hold in practice). Fewer than 3 indices add nothing.
    pub fn push_polygon(&mut self, polygon: &[u32]) {
        if let [first, rest @ ..] = polygon {
            self.triangles.extend(rest.windows(2).map(|pair| [*first, pair[0], pair[1]]));
        }
    }
}
