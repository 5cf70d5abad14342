//! Oriented normals of scanned models against their meshes, at the shared vertices
//! (>= 99% agree in sign after one global flip).

use crate::normals_support;

use normals_support::{area_weighted_vertex_normals, oriented_normals, sign_agreement};
use pointray_io::formats::ply::{read_point_cloud, read_triangle_mesh};
use pointray_test_support::data_dir;

/// The sign agreement between the oriented normals of `points/NAME.ply` and the
/// area-weighted vertex normals of `meshes/NAME.ply`, and how many vertices were compared.
fn agreement_with_mesh(name: &str) -> (f64, usize) {
    let data = data_dir();
    let cloud = read_point_cloud(&data.join(format!("points/{name}.ply"))).expect("points file");
    let mesh = read_triangle_mesh(&data.join(format!("meshes/{name}.ply"))).expect("mesh file");
    assert_eq!(cloud.len(), mesh.positions.len(), "points and mesh share their vertices");
    let points: Vec<glam::Vec3> = cloud.positions.iter().map(|p| p.as_vec3()).collect();
    let normals = oriented_normals(&points);
    let (rate, compared) = sign_agreement(&normals, &area_weighted_vertex_normals(&mesh));
    println!("{name}: {:.4}% of {compared} used vertices agree in sign", rate * 100.0);
    (rate, compared)
}

#[test]
fn bunny_normals_agree_with_mesh_after_one_global_flip() {
    let (rate, compared) = agreement_with_mesh("bunny");
    assert!(compared > 34_000, "only {compared} vertices are used by faces");
    assert!(rate >= 0.99, "bunny sign agreement {rate:.4} < 0.99");
}

#[test]
fn dragon_normals_agree_with_mesh_after_one_global_flip() {
    let (rate, compared) = agreement_with_mesh("dragon_res2");
    assert!(compared > 100_000, "only {compared} vertices are used by faces");
    assert!(rate >= 0.99, "dragon sign agreement {rate:.4} < 0.99");
}
