//! Clouds and meshes written as PLY in each encoding read back unchanged.

use glam::{DVec3, Vec3};
use pointray_io::formats::ply::{self, PlyEncoding};
use pointray_io::{PointCloud, TriangleMesh};

const ENCODINGS: [PlyEncoding; 3] =
    [PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian];

fn full_cloud(offset: f64) -> PointCloud {
    let positions: Vec<DVec3> = (0..50)
        .map(|i| DVec3::new(f64::from(i) * 0.137, -f64::from(i).sqrt(), 1.0 / f64::from(i + 3)) + offset)
        .map(|p| if offset == 0.0 { p.as_vec3().as_dvec3() } else { p })
        .collect();
    PointCloud {
        normals: Some((0..50).map(|i| Vec3::new(i as f32, 1.0, -0.25).normalize()).collect()),
        colors: Some((0..50u8).map(|i| [i, 255 - i, i.wrapping_mul(7)]).collect()),
        intensities: Some((0..50).map(|i| i as f32 / 49.0).collect()),
        classifications: Some((0..50u8).map(|i| i % 19).collect()),
        rings: Some((0..50u16).map(|i| i * 1000).collect()),
        sensor_origins: Some(
            (0..50).map(|i| DVec3::new(f64::from(i % 3) * 12.5, -0.1, 1.75) + offset).collect(),
        ),
        positions,
        ..PointCloud::default()
    }
}

#[test]
fn a_cloud_with_every_attribute_survives_each_encoding() {
    let dir = tempfile::tempdir().unwrap();
    let cloud = full_cloud(0.0);
    for encoding in ENCODINGS {
        let path = dir.path().join(format!("{encoding}.ply"));
        ply::write_point_cloud_as(&path, &cloud, encoding).unwrap();
        let text = std::fs::read(&path).unwrap();
        assert!(text.windows(encoding.to_string().len()).any(|w| w == encoding.to_string().as_bytes()));
        assert_eq!(ply::read_point_cloud(&path).unwrap(), cloud, "{encoding}");
    }
}

#[test]
fn geo_referenced_coordinates_are_written_as_double_and_kept_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let cloud = full_cloud(636_000.123_456_789);
    for encoding in ENCODINGS {
        let path = dir.path().join(format!("geo-{encoding}.ply"));
        ply::write_point_cloud_as(&path, &cloud, encoding).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.windows(15).any(|w| w == b"property double"), "{encoding}: positions not double");
        assert_eq!(ply::read_point_cloud(&path).unwrap().positions, cloud.positions, "{encoding}");
    }
}

#[test]
fn positions_alone_survive_each_encoding_as_float_and_as_double() {
    let dir = tempfile::tempdir().unwrap();
    for offset in [0.0, 636_000.123_456_789] {
        let positions = full_cloud(offset).positions;
        let cloud = PointCloud::from_positions(positions);
        let bodies: Vec<Vec<u8>> = ENCODINGS
            .iter()
            .map(|&encoding| {
                let path = dir.path().join(format!("positions-{offset}-{encoding}.ply"));
                ply::write_point_cloud_as(&path, &cloud, encoding).unwrap();
                assert_eq!(ply::read_point_cloud(&path).unwrap(), cloud, "{encoding}, offset {offset}");
                let bytes = std::fs::read(&path).unwrap();
                let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
                bytes[end..].to_vec()
            })
            .collect();
        // The little-endian body, written straight from the positions, is the big-endian one
        // byte-swapped value by value.
        let value_bytes = if offset == 0.0 { 4 } else { 8 };
        let swapped: Vec<u8> = bodies[2].chunks(value_bytes).flat_map(|v| v.iter().rev().copied()).collect();
        assert!(bodies[1] == swapped, "offset {offset}: little-endian body");
    }
}

#[test]
fn small_coordinates_are_written_as_float() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("small.ply");
    ply::write_point_cloud(&path, &PointCloud::from_positions(vec![DVec3::new(1e5, -2.0, 0.5)])).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.windows(16).any(|w| w == b"property float x"));
    assert!(!bytes.windows(15).any(|w| w == b"property double"));
}

#[test]
fn a_mesh_survives_each_encoding() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.25)],
        triangles: vec![[0, 1, 2], [2, 1, 3]],
    };
    for encoding in ENCODINGS {
        let path = dir.path().join(format!("mesh-{encoding}.ply"));
        ply::write_triangle_mesh_as(&path, &mesh, encoding).unwrap();
        assert_eq!(ply::read_triangle_mesh(&path).unwrap(), mesh, "{encoding}");
    }
}

#[test]
fn the_bunny_mesh_round_trips_bit_for_bit() {
    let data = pointray_test_support::data_dir();
    let mesh = ply::read_triangle_mesh(&data.join("meshes/bunny.ply")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bunny.ply");
    ply::write_triangle_mesh(&path, &mesh).unwrap();
    assert_eq!(ply::read_triangle_mesh(&path).unwrap(), mesh);
}

#[test]
fn writing_inconsistent_data_is_refused_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.ply");
    let mut cloud = full_cloud(0.0);
    cloud.colors.as_mut().unwrap().pop();
    let error = ply::write_point_cloud(&path, &cloud).unwrap_err().to_string();
    assert!(error.contains("50 points but 49 colours"), "{error}");

    let mesh = TriangleMesh { positions: vec![Vec3::ZERO; 3], triangles: vec![[0, 1, 3]] };
    let error = ply::write_triangle_mesh(&path, &mesh).unwrap_err().to_string();
    assert!(error.contains("triangle 0"), "{error}");

    let cloud = PointCloud::from_positions(vec![DVec3::ZERO, DVec3::new(0.0, f64::NAN, 0.0)]);
    let error = ply::write_point_cloud(&path, &cloud).unwrap_err().to_string();
    assert!(error.contains("point 1"), "{error}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}
