//! The shared scan models load with the counts and bounds SOURCES.md gives.

use glam::DVec3;
use pointray_io::formats::ply;

/// (name, vertices, faces, bbox min, bbox max) from data/SOURCES.md.
type Model = (&'static str, usize, usize, [f64; 3], [f64; 3]);

const MODELS: [Model; 3] = [
    ("bunny", 35_947, 69_451, [-0.094690, 0.032987, -0.061874], [0.061009, 0.187321, 0.058800]),
    ("horse", 48_485, 96_966, [-0.042003, -0.091670, -0.076418], [0.042003, 0.091671, 0.076418]),
    ("dragon_res2", 100_250, 202_520, [-0.108188, 0.052739, -0.050345], [0.096406, 0.197139, 0.041137]),
];

#[test]
fn point_files_have_the_documented_counts_and_bounds() {
    let data = pointray_test_support::data_dir();
    for (name, vertices, _, min, max) in MODELS {
        let cloud = ply::read_point_cloud(&data.join(format!("points/{name}.ply"))).unwrap();
        assert_eq!(cloud.len(), vertices, "{name}");
        assert!(cloud.normals.is_none() && cloud.colors.is_none() && cloud.intensities.is_none());
        let lower = cloud.positions.iter().fold(DVec3::INFINITY, |a, p| a.min(*p));
        let upper = cloud.positions.iter().fold(DVec3::NEG_INFINITY, |a, p| a.max(*p));
        assert!(lower.abs_diff_eq(DVec3::from(min), 1e-6), "{name}: min {lower}");
        assert!(upper.abs_diff_eq(DVec3::from(max), 1e-6), "{name}: max {upper}");
    }
}

#[test]
fn mesh_files_have_the_documented_counts() {
    let data = pointray_test_support::data_dir();
    for (name, vertices, faces, _, _) in MODELS {
        let mesh = ply::read_triangle_mesh(&data.join(format!("meshes/{name}.ply"))).unwrap();
        assert_eq!(mesh.positions.len(), vertices, "{name}");
        assert_eq!(mesh.triangles.len(), faces, "{name}");
    }
}

#[test]
fn mesh_vertices_equal_the_point_file_vertices() {
    let data = pointray_test_support::data_dir();
    let mesh = ply::read_triangle_mesh(&data.join("meshes/bunny.ply")).unwrap();
    let cloud = ply::read_point_cloud(&data.join("points/bunny.ply")).unwrap();
    let cloud_as_f32: Vec<_> = cloud.positions.iter().map(|p| p.as_vec3()).collect();
    assert_eq!(mesh.positions, cloud_as_f32);
}

#[test]
fn a_mesh_file_reads_as_a_point_cloud_of_its_vertices() {
    let data = pointray_test_support::data_dir();
    let cloud = ply::read_point_cloud(&data.join("meshes/horse.ply")).unwrap();
    assert_eq!(cloud.len(), 48_485);
}
