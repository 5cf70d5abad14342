//! Shared by the `normals_*` tests and `examples/normals_pipeline.rs`: the stages chained as `prep` chains them, and comparison with a mesh's normals.

use glam::Vec3;
use pointray_io::TriangleMesh;
use pointray_surface::morton::morton_order;
use pointray_surface::neighbors::k_nearest;
use pointray_surface::normals::pca_normals;
use pointray_surface::orientation::orient_consistently;

/// `prep`'s defaults: 9 neighbours for the fit, 16 for the normal.
pub const FIT_K: usize = 9;
pub const NORMAL_K: usize = 16;

/// Oriented normals computed the way `prep` does: Morton order, one kNN table for both
/// k's, PCA, orientation; returned in the input's order.
pub fn oriented_normals(points: &[Vec3]) -> Vec<Vec3> {
    let order = morton_order(points);
    let sorted: Vec<Vec3> = order.iter().map(|&i| points[i as usize]).collect();
    let neighbors = k_nearest(&sorted, FIT_K.max(NORMAL_K));
    let mut normals = pca_normals(&sorted, &neighbors, NORMAL_K);
    orient_consistently(&sorted, &mut normals, &neighbors);
    let mut in_input_order = vec![Vec3::ZERO; points.len()];
    for (sorted_index, &input_index) in order.iter().enumerate() {
        in_input_order[input_index as usize] = normals[sorted_index];
    }
    in_input_order
}

/// Per vertex, the sum of its faces' unnormalised normals (area-weighted); zero for a
/// vertex no face uses.
pub fn area_weighted_vertex_normals(mesh: &TriangleMesh) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; mesh.positions.len()];
    for (t, triangle) in mesh.triangles.iter().enumerate() {
        let face_normal = mesh.face_normal(t);
        for &v in triangle {
            normals[v as usize] += face_normal;
        }
    }
    normals
}

/// How many of `normals` agree in sign with `reference` (zero references skipped), as a
/// fraction, after the one global flip that agrees best; and how many were compared.
pub fn sign_agreement(normals: &[Vec3], reference: &[Vec3]) -> (f64, usize) {
    let pairs = normals.iter().zip(reference).filter(|(_, r)| **r != Vec3::ZERO);
    let (mut agree, mut compared) = (0usize, 0usize);
    for (n, r) in pairs {
        compared += 1;
        agree += usize::from(n.dot(*r) > 0.0);
    }
    let best = agree.max(compared - agree);
    (best as f64 / compared.max(1) as f64, compared)
}

/// The angle in degrees between two directions, ignoring sign.
pub fn line_angle_degrees(a: Vec3, b: Vec3) -> f32 {
    let cosine = (a.normalize().dot(b.normalize())).abs().min(1.0);
    cosine.acos().to_degrees()
}
