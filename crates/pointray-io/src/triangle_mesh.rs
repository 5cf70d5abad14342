//! An indexed triangle mesh.

use glam::Vec3;

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
}
