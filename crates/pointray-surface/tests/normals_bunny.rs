//! Oriented normals of the scanned bunny against its mesh (issue 2: >= 99% agree in sign).

mod normals_support;

use normals_support::{area_weighted_vertex_normals, data_dir, oriented_normals, sign_agreement};
use pointray_io::formats::ply::{read_point_cloud, read_triangle_mesh};

#[test]
fn bunny_normals_agree_with_mesh_after_one_global_flip() {
    let Some(data) = data_dir() else { return };
    let cloud = read_point_cloud(&data.join("points/bunny.ply")).expect("bunny points");
    let mesh = read_triangle_mesh(&data.join("meshes/bunny.ply")).expect("bunny mesh");
    assert_eq!(cloud.len(), mesh.positions.len(), "points and mesh share their vertices");
    let points: Vec<glam::Vec3> = cloud.positions.iter().map(|p| p.as_vec3()).collect();

    let normals = oriented_normals(&points);
    let (rate, compared) = sign_agreement(&normals, &area_weighted_vertex_normals(&mesh));

    println!("bunny: {:.4}% of {compared} used vertices agree in sign", rate * 100.0);
    assert!(compared > 34_000, "only {compared} vertices are used by faces");
    assert!(rate >= 0.99, "bunny sign agreement {rate:.4} < 0.99");
}
