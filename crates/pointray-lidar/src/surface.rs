//! A named triangle mesh in world coordinates with its reflectance: what the street is built
//! of, and what is written out as its ground-truth mesh.

use glam::Vec3;
use pointray_io::TriangleMesh;

#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// Its first word gives the class of its returns (`Classification::of_object_named`).
    pub name: String,
    pub mesh: TriangleMesh,
    /// The fraction of the laser's light a surface facing the sensor sends back, in [0, 1].
    pub reflectance: f32,
}

impl Surface {
    pub fn new(name: impl Into<String>, mesh: TriangleMesh, reflectance: f32) -> Self {
        Self { name: name.into(), mesh, reflectance }
    }

    /// A problem that would make its returns meaningless, if any.
    pub(crate) fn problem(&self) -> Option<String> {
        if !(0.0..=1.0).contains(&self.reflectance) {
            return Some(format!("reflectance {} is outside [0, 1]", self.reflectance));
        }
        if self.mesh.triangles.is_empty() {
            return Some("it has no triangles".into());
        }
        if let Some(index) = self.mesh.positions.iter().position(|p| !p.is_finite()) {
            return Some(format!("vertex {index} is not finite: {}", self.mesh.positions[index]));
        }
        let count = self.mesh.positions.len();
        let bad = self.mesh.triangles.iter().position(|t| t.iter().any(|&i| i as usize >= count))?;
        Some(format!("triangle {bad} names a vertex beyond its {count}"))
    }
}

/// Every surface in one mesh, for the ground truth of a scan.
pub fn merged_mesh(surfaces: &[Surface]) -> TriangleMesh {
    let mut merged = TriangleMesh::default();
    for surface in surfaces {
        let base = merged.positions.len() as u32;
        merged.positions.extend_from_slice(&surface.mesh.positions);
        merged.triangles.extend(surface.mesh.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    merged
}

/// The luminance of a linear RGB colour (Rec. 709 weights): a scene file's diffuse colour read
/// as the reflectance the laser sees.
pub fn reflectance_of(diffuse: Vec3) -> f32 {
    diffuse.dot(Vec3::new(0.2126, 0.7152, 0.0722)).clamp(0.0, 1.0)
}
