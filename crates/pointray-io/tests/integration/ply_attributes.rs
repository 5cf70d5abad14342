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

#[test]
fn rings_and_classifications_of_any_integer_type_are_read() {
    let text = ascii_vertices(
        &["float x", "float y", "float z", "uchar ring", "int classification"],
        &["0 0 0 31 2", "1 0 0 0 6"],
    );
    let (_dir, path) = fixture("rings.ply", text.as_bytes());
    let cloud = ply::read_point_cloud(&path).unwrap();
    assert_eq!(cloud.rings, Some(vec![31, 0]));
    assert_eq!(cloud.classifications, Some(vec![2, 6]));
    assert_eq!(cloud.sensor_origins, None);
}

/// The layout `pointray scan` writes: binary little-endian, x y z double, intensity float,
/// ring ushort, azimuth and time float (skipped), classification uchar, sensor_x sensor_y
/// sensor_z double.
#[test]
fn the_scanner_layout_reads_right() {
    let header = "ply\nformat binary_little_endian 1.0\ncomment written by a scanner\nelement vertex 2\n\
                  property double x\nproperty double y\nproperty double z\nproperty float intensity\n\
                  property ushort ring\nproperty float azimuth\nproperty float time\n\
                  property uchar classification\nproperty double sensor_x\nproperty double sensor_y\n\
                  property double sensor_z\nend_header\n";
    let points = [
        ([12.5, -3.25, 0.125], 0.75f32, 17u16, 1.5f32, 0.05f32, 2u8, [0.0, 0.0, 1.8]),
        ([-40.0, 8.0, 2.5], 0.25, 63, -3.0, 0.1, 6, [10.0, 0.0, 1.8]),
    ];
    let mut bytes = header.as_bytes().to_vec();
    for (position, intensity, ring, azimuth, time, class, sensor) in points {
        position.iter().for_each(|v: &f64| bytes.extend(v.to_le_bytes()));
        bytes.extend(intensity.to_le_bytes());
        bytes.extend(ring.to_le_bytes());
        bytes.extend(azimuth.to_le_bytes());
        bytes.extend(time.to_le_bytes());
        bytes.push(class);
        sensor.iter().for_each(|v: &f64| bytes.extend(v.to_le_bytes()));
    }
    let (_dir, path) = fixture("scan.ply", &bytes);
    let cloud = ply::read_point_cloud(&path).unwrap();
    assert_eq!(cloud.positions, points.map(|p| DVec3::from(p.0)).to_vec());
    assert_eq!(cloud.intensities, Some(vec![0.75, 0.25]));
    assert_eq!(cloud.rings, Some(vec![17, 63]));
    assert_eq!(cloud.classifications, Some(vec![2, 6]));
    assert_eq!(cloud.sensor_origins, Some(points.map(|p| DVec3::from(p.6)).to_vec()));
    assert_eq!(cloud.sensor_of(1), Some(DVec3::new(10.0, 0.0, 1.8)));
}

/// A binary cloud of `count` points (x, y, z, intensity as floats), point `i` at (i, 0, 0)
/// with intensity 150, but for the `changed` points.
fn binary_cloud(count: usize, changed: &[(usize, [f32; 4])]) -> Vec<u8> {
    binary_cloud_with(count, "intensity", changed)
}

/// A binary cloud of `count` points whose fourth float is the property `fourth`.
fn binary_cloud_with(count: usize, fourth: &str, changed: &[(usize, [f32; 4])]) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {count}\nproperty float x\n\
         property float y\nproperty float z\nproperty float {fourth}\nend_header\n"
    );
    let mut rows: Vec<[f32; 4]> = (0..count).map(|i| [i as f32, 0.0, 0.0, 150.0]).collect();
    for &(i, row) in changed {
        rows[i] = row;
    }
    let body = rows.iter().flatten().flat_map(|value| value.to_le_bytes());
    header.bytes().chain(body).collect()
}

#[test]
fn a_binary_cloud_read_whole_in_chunks_is_scaled_and_checked_as_one() {
    // More points than one chunk of the whole read holds.
    let count = (1 << 20) + 5;
    let last = count - 1;
    let (_dir, path) = fixture("strengths.ply", &binary_cloud(count, &[(last, [0.0, 0.0, 0.0, 600.0])]));
    let cloud = ply::read_point_cloud(&path).unwrap();
    assert_eq!(cloud.len(), count);
    assert_eq!(cloud.positions[last - 1], DVec3::new((last - 1) as f64, 0.0, 0.0));
    let intensities = cloud.intensities.unwrap();
    assert_eq!((intensities[0], intensities[last]), (0.25, 1.0), "divided by the largest of the file");

    let (_dir, path) = fixture("nan.ply", &binary_cloud(count, &[(last - 2, [f32::NAN, 0.0, 0.0, 1.0])]));
    let error = ply::read_point_cloud(&path).unwrap_err().to_string();
    assert!(error.contains(&format!("point {} has a non-finite coordinate", last - 2)), "{error}");
    assert!(error.contains("nan.ply"), "{error}");
}

#[test]
fn a_binary_cloud_of_positions_alone_is_read_in_chunks_and_checked() {
    // Positions are decoded alone, past a property no attribute takes.
    let count = (1 << 20) + 5;
    let last = count - 1;
    let (_dir, path) = fixture("plain.ply", &binary_cloud_with(count, "unused", &[]));
    let cloud = ply::read_point_cloud(&path).unwrap();
    assert_eq!((cloud.len(), cloud.intensities), (count, None));
    assert_eq!(cloud.positions[last], DVec3::new(last as f64, 0.0, 0.0));

    let nan = [(last - 2, [0.0, f32::INFINITY, 0.0, 1.0])];
    let (_dir, path) = fixture("inf.ply", &binary_cloud_with(count, "unused", &nan));
    let error = ply::read_point_cloud(&path).unwrap_err().to_string();
    assert!(error.contains(&format!("point {} has a non-finite coordinate", last - 2)), "{error}");
    assert!(error.contains("inf.ply"), "{error}");
}
