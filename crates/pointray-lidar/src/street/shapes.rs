//! Mesh pieces for the street: flat polygons, boxes, bevelled boxes and cylinders, each
//! wound so that its normals point out of the solid (or up, for the ground).
//!
//! Flat faces get their own vertices, so that interpolated vertex normals stay flat across
//! each face and sharp at its edges; a cylinder's side shares its vertices, so that its
//! normals interpolate round.

use glam::Vec3;
use pointray_io::TriangleMesh;

/// Appends a planar convex polygon, its corners in order around it, facing away from `inside`.
pub fn push_face(mesh: &mut TriangleMesh, corners: &[Vec3], inside: Vec3) {
    let base = mesh.positions.len() as u32;
    mesh.positions.extend_from_slice(corners);
    let indices: Vec<u32> = (base..base + corners.len() as u32).collect();
    push_polygon(mesh, &indices, inside);
}

/// Appends a convex polygon over existing vertices, facing away from `inside`.
fn push_polygon(mesh: &mut TriangleMesh, indices: &[u32], inside: Vec3) {
    let corners: Vec<Vec3> = indices.iter().map(|&i| mesh.positions[i as usize]).collect();
    let centroid = corners.iter().sum::<Vec3>() / corners.len() as f32;
    if newell_normal(&corners).dot(centroid - inside) >= 0.0 {
        mesh.push_polygon(indices);
    } else {
        let reversed: Vec<u32> = indices.iter().rev().copied().collect();
        mesh.push_polygon(&reversed);
    }
}

/// Twice a polygon's area along its normal, by Newell's method: the sum of its consecutive
/// corners' cross products, which follows the winding even where three corners are collinear.
fn newell_normal(corners: &[Vec3]) -> Vec3 {
    let next = corners.iter().cycle().skip(1);
    corners.iter().zip(next).map(|(a, b)| a.cross(*b)).sum()
}

/// An axis-aligned box.
pub fn push_box(mesh: &mut TriangleMesh, min: Vec3, max: Vec3) {
    push_bevelled_box(mesh, min, max, 0.0);
}

/// An axis-aligned box whose twelve edges are cut at 45° by `bevel` (0 for a plain box): a
/// car's body. `bevel` must be under half the box's smallest side.
pub fn push_bevelled_box(mesh: &mut TriangleMesh, min: Vec3, max: Vec3, bevel: f32) {
    let center = (min + max) * 0.5;
    let half = (max - min) * 0.5;
    // The vertex that corner `signs` contributes to the face across `axis`.
    let vertex = |signs: [f32; 3], axis: usize| {
        Vec3::from_array(std::array::from_fn(|i| {
            let inset = if i == axis { half[i] } else { half[i] - bevel };
            center[i] + signs[i] * inset
        }))
    };
    let sign = |bit: bool| if bit { 1.0 } else { -1.0 };
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [-1.0, 1.0] {
            // The face across `axis` on `side`, its corners in order around it.
            let corners: Vec<Vec3> = [(false, false), (true, false), (true, true), (false, true)]
                .iter()
                .map(|&(su, sv)| {
                    let mut signs = [0.0; 3];
                    (signs[axis], signs[u], signs[v]) = (side, sign(su), sign(sv));
                    vertex(signs, axis)
                })
                .collect();
            push_face(mesh, &corners, center);
        }
        if bevel > 0.0 {
            push_edge_bevels(mesh, axis, &vertex, center);
        }
    }
    if bevel > 0.0 {
        for corner in 0..8 {
            let signs = [sign(corner & 1 != 0), sign(corner & 2 != 0), sign(corner & 4 != 0)];
            push_face(mesh, &[vertex(signs, 0), vertex(signs, 1), vertex(signs, 2)], center);
        }
    }
}

/// The four bevels along the edges parallel to `axis`.
fn push_edge_bevels(
    mesh: &mut TriangleMesh,
    axis: usize,
    vertex: &dyn Fn([f32; 3], usize) -> Vec3,
    center: Vec3,
) {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let at = |along: f32| {
            let mut signs = [0.0; 3];
            (signs[axis], signs[u], signs[v]) = (along, su, sv);
            signs
        };
        let corners = [vertex(at(-1.0), u), vertex(at(1.0), u), vertex(at(1.0), v), vertex(at(-1.0), v)];
        push_face(mesh, &corners, center);
    }
}

/// A closed cylinder of `sides` flat sides from `base` along `axis` (unit) for `length`.
pub fn push_cylinder(mesh: &mut TriangleMesh, base: Vec3, axis: Vec3, radius: f32, length: f32, sides: u32) {
    let (across, other) = axis.any_orthonormal_pair();
    let top = base + axis * length;
    let center = (base + top) * 0.5;
    let rim = |i: u32| {
        let angle = std::f32::consts::TAU * i as f32 / sides as f32;
        (across * angle.cos() + other * angle.sin()) * radius
    };
    let first = mesh.positions.len() as u32;
    for i in 0..sides {
        mesh.positions.extend([base + rim(i), top + rim(i)]);
    }
    for i in 0..sides {
        let next = (i + 1) % sides;
        let quad = [first + 2 * i, first + 2 * next, first + 2 * next + 1, first + 2 * i + 1];
        push_polygon(mesh, &quad, center);
    }
    for end in [base, top] {
        let cap: Vec<Vec3> = (0..sides).map(|i| end + rim(i)).collect();
        push_face(mesh, &cap, center);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The signed volume by the divergence theorem: the solid's volume when every face points
    /// out, negative when they point in.
    fn volume(mesh: &TriangleMesh) -> f32 {
        (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.triangles[t].map(|i| mesh.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn solids_face_outward_and_enclose_their_volume() {
        let mut plain = TriangleMesh::default();
        push_box(&mut plain, Vec3::new(1.0, 2.0, 3.0), Vec3::new(3.0, 5.0, 4.0));
        assert!((volume(&plain) - 6.0).abs() < 1e-4, "{}", volume(&plain));

        let mut bevelled = TriangleMesh::default();
        push_bevelled_box(&mut bevelled, Vec3::ZERO, Vec3::ONE, 0.1);
        // The cube less 12 edge prisms (c²/2 · (1 − 2c) each), and less 5/6 of each of the 8
        // corner cubes of side c (the cut keeps a tetrahedron of c³/6 in each).
        let c: f32 = 0.1;
        let expected = 1.0 - 12.0 * c * c / 2.0 * (1.0 - 2.0 * c) - 8.0 * c * c * c * 5.0 / 6.0;
        assert!((volume(&bevelled) - expected).abs() < 1e-4, "{} vs {expected}", volume(&bevelled));
        assert_eq!(bevelled.triangles.len(), 6 * 2 + 12 * 2 + 8);

        let mut cylinder = TriangleMesh::default();
        push_cylinder(&mut cylinder, Vec3::new(5.0, 0.0, 0.0), Vec3::Z, 1.0, 2.0, 64);
        let prism_area = 0.5 * 64.0 * (std::f32::consts::TAU / 64.0).sin();
        assert!((volume(&cylinder) - 2.0 * prism_area).abs() < 1e-3);
    }
}
