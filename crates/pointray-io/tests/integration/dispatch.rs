//! `formats::read_point_cloud` and `read_triangle_mesh` choose the right reader.

use crate::common;

use common::fixture;
use pointray_io::IoError;
use pointray_io::formats::{self, ply};

const ASCII_TRIANGLE: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                              property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                              end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

#[test]
fn ply_content_is_read_as_ply_whatever_the_name() {
    for name in ["mesh.ply", "mesh.xyz", "mesh"] {
        let (_dir, path) = fixture(name, ASCII_TRIANGLE.as_bytes());
        assert_eq!(formats::read_triangle_mesh(&path).unwrap().triangles, vec![[0, 1, 2]], "{name}");
        assert_eq!(formats::read_point_cloud(&path).unwrap().len(), 3, "{name}");
    }
}

#[test]
fn bad_ply_files_reach_the_ply_reader_and_its_errors() {
    let (_dir, path) = fixture("empty.ply", b"");
    assert!(formats::read_point_cloud(&path).unwrap_err().to_string().contains("empty file"));
    let (_dir, path) = fixture("fake.ply", &[0x89, b'P', b'N', b'G', 0, 0, 0xff]);
    assert!(formats::read_point_cloud(&path).unwrap_err().to_string().contains("not a PLY file"));
}

#[test]
fn an_unknown_binary_file_lists_the_supported_formats() {
    let (_dir, path) = fixture("blob.dat", &[0, 159, 146, 150, 0xff]);
    let error = formats::read_point_cloud(&path).unwrap_err();
    assert!(matches!(error, IoError::Unsupported { .. }));
    let message = error.to_string();
    assert!(message.contains("blob.dat") && message.contains("PLY") && message.contains("OBJ"), "{message}");
}

#[test]
fn point_only_formats_are_not_meshes() {
    let (_dir, path) = fixture("cloud.xyz", b"0 0 0\n1 1 1\n");
    assert_eq!(formats::read_point_cloud(&path).unwrap().len(), 2);
    assert!(matches!(formats::read_triangle_mesh(&path), Err(IoError::Unsupported { .. })));
}

#[test]
fn the_shared_las_scan_is_dispatched_to_the_las_reader() {
    let data = pointray_test_support::data_dir();
    assert_eq!(formats::read_point_cloud(&data.join("scans/autzen_trim.las")).unwrap().len(), 110_000);
    let bunny = formats::read_point_cloud(&data.join("points/bunny.ply")).unwrap();
    assert_eq!(bunny, ply::read_point_cloud(&data.join("points/bunny.ply")).unwrap());
}
