//! Optional vertex attributes in their various stored types, and polygon faces.

use crate::common;

use common::fixture;
use glam::{DVec3, Vec3};
use pointray_io::formats::ply;

fn ascii_vertices(properties: &[&str], rows: &[&str]) -> String {
    let declared: String = properties.iter().map(|p| format!("property {p}\n")).collect();
    format!(
        "ply\nformat ascii 1.0\nelement vertex {}\n{declared}end_header\n{}\n",
        rows.len(),
        rows.join("\n")
    )
}

#[test]
fn uchar_and_float_colours_reach_the_same_bytes() {
    let uchar = ascii_vertices(
        &["float x", "float y", "float z", "uchar red", "uchar green", "uchar blue"],
        &["0 0 0 255 128 0"],
    );
    let float = ascii_vertices(
        &["float x", "float y", "float z", "float red", "float green", "float blue"],
        &["0 0 0 1.0 0.50196 -0.5"],
    );
    let ushort = ascii_vertices(
        &["float x", "float y", "float z", "ushort red", "ushort green", "ushort blue"],
        &["0 0 0 65535 32896 0"],
    );
    for (name, text) in [("uchar.ply", uchar), ("float.ply", float), ("ushort.ply", ushort)] {
        let (_dir, path) = fixture(name, text.as_bytes());
        assert_eq!(ply::read_point_cloud(&path).unwrap().colors, Some(vec![[255, 128, 0]]), "{name}");
    }
}

#[test]
fn positions_of_any_numeric_type_and_normals_are_read() {
    let text = ascii_vertices(
        &["int x", "short y", "double z", "float nx", "float ny", "float nz", "float confidence"],
        &["-3 7 0.25 0 0 1 0.9", "100000 -2 1e-3 1 0 0 0.1"],
    );
    let (_dir, path) = fixture("types.ply", text.as_bytes());
    let cloud = ply::read_point_cloud(&path).unwrap();
    assert_eq!(cloud.positions, vec![DVec3::new(-3.0, 7.0, 0.25), DVec3::new(100_000.0, -2.0, 1e-3)]);
    assert_eq!(cloud.normals, Some(vec![Vec3::Z, Vec3::X]));
    assert_eq!(cloud.colors, None);
}

#[test]
fn an_incomplete_normal_group_is_not_read_as_normals() {
    let text = ascii_vertices(&["float x", "float y", "float z", "float nx", "float ny"], &["0 0 0 1 0"]);
    let (_dir, path) = fixture("partial.ply", text.as_bytes());
    assert_eq!(ply::read_point_cloud(&path).unwrap().normals, None);
}

#[test]
fn intensities_are_brought_to_the_unit_interval() {
    let cases = [
        ("uchar intensity", ["0", "51", "255"], [0.0, 0.2, 1.0]),
        ("float scalar_intensity", ["0", "0.5", "1"], [0.0, 0.5, 1.0]),
        // Raw return strengths above 1 are scaled by the largest.
        ("float intensity", ["0", "150", "600"], [0.0, 0.25, 1.0]),
    ];
    for (property, values, expected) in cases {
        let rows: Vec<String> = values.iter().map(|v| format!("0 0 0 {v}")).collect();
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        let text = ascii_vertices(&["float x", "float y", "float z", property], &rows);
        let (_dir, path) = fixture("intensity.ply", text.as_bytes());
        assert_eq!(ply::read_point_cloud(&path).unwrap().intensities, Some(expected.to_vec()), "{property}");
    }
}

#[test]
fn polygons_are_fan_triangulated_whatever_the_index_name_and_type() {
    let text = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n\
                element face 2\nproperty uchar flags\nproperty list ushort short vertex_index\nend_header\n\
                0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n7 5 0 1 2 3 4\n0 3 4 3 2\n";
    let (_dir, path) = fixture("polygons.ply", text.as_bytes());
    let mesh = ply::read_triangle_mesh(&path).unwrap();
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [4, 3, 2]]);
}
