//! Meshes the renderers' tests share.

use glam::Vec3;
use pointray_io::TriangleMesh;

/// A closed UV sphere of `rings` × `segments` quads (two triangles each) at the origin,
/// wound so that its face normals point outward.
pub fn sphere_mesh(radius: f32, rings: u32, segments: u32) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for ring in 0..=rings {
        let polar = std::f32::consts::PI * ring as f32 / rings as f32;
        for segment in 0..segments {
            let azimuth = std::f32::consts::TAU * segment as f32 / segments as f32;
            let direction = Vec3::new(polar.sin() * azimuth.cos(), polar.cos(), polar.sin() * azimuth.sin());
            mesh.positions.push(radius * direction);
        }
    }
    let index = |ring: u32, segment: u32| ring * segments + segment % segments;
    for ring in 0..rings {
        for segment in 0..segments {
            let (a, b) = (index(ring, segment), index(ring, segment + 1));
            let (c, d) = (index(ring + 1, segment), index(ring + 1, segment + 1));
            mesh.triangles.push([a, b, d]);
            mesh.triangles.push([a, d, c]);
        }
    }
    mesh
}
