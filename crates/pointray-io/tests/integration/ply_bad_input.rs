//! Malformed PLY files give an error naming the file and the problem, never a panic.

use crate::common;

use common::fixture;
use pointray_io::formats::ply;

const HEADER_3_FLOATS: &str = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n\
                               property float x\nproperty float y\nproperty float z\nend_header\n";

fn binary_body(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn cloud_error(name: &str, bytes: &[u8]) -> String {
    let (_dir, path) = fixture(name, bytes);
    let error = ply::read_point_cloud(&path).expect_err("malformed input was accepted").to_string();
    assert!(error.contains(name), "error does not name the file: {error}");
    error
}

fn mesh_error(name: &str, bytes: &[u8]) -> String {
    let (_dir, path) = fixture(name, bytes);
    let error = ply::read_triangle_mesh(&path).expect_err("malformed input was accepted").to_string();
    assert!(error.contains(name), "error does not name the file: {error}");
    error
}

#[test]
fn an_empty_file_is_refused() {
    assert!(cloud_error("empty.ply", b"").contains("empty file"));
}

#[test]
fn a_non_ply_file_is_refused() {
    let error = cloud_error("fake.ply", b"solid cube\nfacet normal 0 0 1\n");
    assert!(error.contains("not a PLY file"), "{error}");
}

#[test]
fn a_header_without_end_is_refused() {
    let error = cloud_error("open.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
    assert!(error.contains("header"), "{error}");
}

#[test]
fn a_truncated_binary_body_is_refused() {
    let mut bytes = HEADER_3_FLOATS.as_bytes().to_vec();
    bytes.extend(binary_body(&[0.0; 8]));
    let error = cloud_error("truncated.ply", &bytes);
    assert!(error.contains("truncated"), "{error}");
}

#[test]
fn a_header_overstating_its_count_is_refused() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 0 0\n1 1 1\n2 2 2\n";
    let error = cloud_error("more.ply", ascii.as_bytes());
    assert!(error.contains("vertex"), "{error}");
}

#[test]
fn a_header_understating_its_count_is_refused() {
    let mut bytes = HEADER_3_FLOATS.as_bytes().to_vec();
    bytes.extend(binary_body(&[0.0; 12]));
    let error = cloud_error("fewer.ply", &bytes);
    assert!(error.contains("12 bytes follow the last element"), "{error}");

    let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 0 0\n1 1 1\n";
    let error = cloud_error("fewer_ascii.ply", ascii.as_bytes());
    assert!(error.contains("do not match"), "{error}");
}

#[test]
fn trailing_blank_lines_in_ascii_are_accepted() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 0 0\n\n\n";
    let (_dir, path) = fixture("blank.ply", ascii.as_bytes());
    assert_eq!(ply::read_point_cloud(&path).unwrap().len(), 1);
}

#[test]
fn an_impossibly_large_count_is_refused_without_allocating_it() {
    let header = HEADER_3_FLOATS.replace("vertex 3", "vertex 18446744073709551615");
    let error = cloud_error("huge.ply", header.as_bytes());
    assert!(error.contains("impossibly large"), "{error}");
}

#[test]
fn an_element_without_properties_cannot_spin_forever() {
    let header = HEADER_3_FLOATS.replace("end_header", "element nothing 4000000000000\nend_header");
    let mut bytes = header.into_bytes();
    bytes.extend(binary_body(&[0.0; 9]));
    let error = cloud_error("spin.ply", &bytes);
    assert!(error.contains("no properties"), "{error}");
}

#[test]
fn non_finite_coordinates_name_the_point() {
    let mut bytes = HEADER_3_FLOATS.as_bytes().to_vec();
    bytes.extend(binary_body(&[0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, f32::NAN, 2.0]));
    let error = cloud_error("nan.ply", &bytes);
    assert!(error.contains("point 2") && error.contains("non-finite"), "{error}");

    let ascii = "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n\
                 property double z\nend_header\n0 1e999 0\n1 1 1\n";
    let error = cloud_error("inf.ply", ascii.as_bytes());
    assert!(error.contains("point 0") && error.contains("non-finite"), "{error}");
}

#[test]
fn a_file_without_vertices_or_positions_is_refused() {
    let error = cloud_error(
        "novertex.ply",
        b"ply\nformat ascii 1.0\nelement point 0\nproperty float x\nend_header\n",
    );
    assert!(error.contains("no 'vertex' element"), "{error}");
    let error = cloud_error(
        "noz.ply",
        b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nend_header\n",
    );
    assert!(error.contains("'z'"), "{error}");
}

#[test]
fn garbage_in_an_ascii_body_names_the_element() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 zero 0\n";
    let error = cloud_error("garbage.ply", ascii.as_bytes());
    assert!(error.contains("element 'vertex'"), "{error}");
}

const MESH_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                           property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
                           0 0 0\n1 0 0\n1 1 0\n0 1 0\n";

#[test]
fn faces_out_of_range_or_negative_are_refused() {
    let error = mesh_error("range.ply", format!("{MESH_HEADER}3 0 1 4\n").as_bytes());
    assert!(error.contains("face 0 refers to vertex 4"), "{error}");
    let error = mesh_error("negative.ply", format!("{MESH_HEADER}3 0 -1 2\n").as_bytes());
    assert!(error.contains("negative"), "{error}");
    let error = mesh_error("short.ply", format!("{MESH_HEADER}2 0 1\n").as_bytes());
    assert!(error.contains("at least 3"), "{error}");
}

#[test]
fn a_points_file_is_not_a_mesh() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 0 0\n";
    assert!(mesh_error("points.ply", ascii.as_bytes()).contains("no 'face' element"));
}

#[test]
fn float_face_indices_are_refused() {
    let header = MESH_HEADER.replace("list uchar int", "list uchar float");
    let error = mesh_error("floatfaces.ply", format!("{header}3 0 1 2\n").as_bytes());
    assert!(error.contains("list of integers"), "{error}");
}

/// Cutting a real file anywhere, or corrupting its header, must give an error, not a panic.
#[test]
fn truncations_and_header_corruptions_never_panic() {
    let mut mesh = MESH_HEADER.replace("ascii", "binary_big_endian").replace("int vertex", "uint vertex");
    mesh.truncate(mesh.find("0 0 0\n").unwrap());
    let mut bytes = mesh.into_bytes();
    bytes.extend(
        [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0].iter().flat_map(|v| v.to_be_bytes()),
    );
    bytes.push(4);
    bytes.extend([0u32, 1, 2, 3].iter().flat_map(|v| v.to_be_bytes()));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mutant.ply");
    std::fs::write(&path, &bytes).unwrap();
    assert_eq!(ply::read_triangle_mesh(&path).unwrap().triangles, vec![[0, 1, 2], [0, 2, 3]]);
    for cut in 0..bytes.len() {
        std::fs::write(&path, &bytes[..cut]).unwrap();
        assert!(ply::read_triangle_mesh(&path).is_err(), "cut at {cut} was accepted");
    }
    let header_length = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    for position in 0..header_length {
        for replacement in [b' ', b'\n', b'9', b'x', 0xff] {
            let mut mutant = bytes.clone();
            mutant[position] = replacement;
            std::fs::write(&path, &mutant).unwrap();
            let _ = ply::read_triangle_mesh(&path);
            let _ = ply::read_point_cloud(&path);
        }
    }
}

#[test]
fn a_property_declared_twice_is_refused_in_ascii_and_binary() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                 property float y\nproperty float z\nend_header\n0 1 2 3\n";
    let error = cloud_error("twice.ply", ascii.as_bytes());
    assert!(error.contains("element 'vertex' declares property 'y' twice"), "{error}");

    let header = HEADER_3_FLOATS.replace("property float z\n", "property float z\nproperty float x\n");
    let mut bytes = header.into_bytes();
    bytes.extend(binary_body(&[0.0; 12]));
    let error = cloud_error("twice_binary.ply", &bytes);
    assert!(error.contains("declares property 'x' twice"), "{error}");
    assert!(!error.contains("bytes follow"), "{error}");
}

#[test]
fn an_element_declared_twice_is_refused() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                 property float z\nelement vertex 1\nproperty float w\nend_header\n0 1 2\n3\n";
    assert!(cloud_error("elements.ply", ascii.as_bytes()).contains("declares element 'vertex' twice"));
}

#[test]
fn an_ascii_line_with_more_or_fewer_values_than_properties_is_refused() {
    let ascii = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 1 2\n3 4 5 6\n";
    let error = cloud_error("extra.ply", ascii.as_bytes());
    assert!(error.contains("element 'vertex' entry 1: 4 values, but its properties take 3"), "{error}");
    let mesh = format!("{MESH_HEADER}3 0 1 2 3\n");
    let error = mesh_error("extra_index.ply", mesh.as_bytes());
    assert!(error.contains("element 'face' entry 0: 5 values, but its properties take 4"), "{error}");
}

#[test]
fn rings_and_classifications_must_be_integers_in_range() {
    let header = |property: &str| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
             property float z\nproperty {property}\nend_header\n"
        )
    };
    let error = cloud_error("float_ring.ply", format!("{}0 0 0 3\n", header("float ring")).as_bytes());
    assert!(error.contains("'ring' is a floating-point number"), "{error}");
    let error = cloud_error("negative_ring.ply", format!("{}0 0 0 -1\n", header("int ring")).as_bytes());
    assert!(error.contains("point 0 has ring -1"), "{error}");
    let error =
        cloud_error("wide_class.ply", format!("{}0 0 0 256\n", header("short classification")).as_bytes());
    assert!(error.contains("point 0 has classification 256"), "{error}");
}

/// A header of 100k properties, or of 50k elements, is checked in time linear in its size:
/// each name against the names before it took 28 s and 15 s.
#[test]
fn huge_headers_are_read_in_linear_time() {
    let dir = tempfile::tempdir().unwrap();
    let start = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n\
                 property float x\nproperty float y\nproperty float z\n";
    let properties: String = (0..100_000).map(|i| format!("property uchar p{i}\n")).collect();
    let elements: String = (0..50_000).map(|i| format!("element e{i} 0\nproperty uchar v\n")).collect();
    for (name, middle, body) in [("properties.ply", properties, 12 + 100_000), ("elements.ply", elements, 12)]
    {
        let path = dir.path().join(name);
        std::fs::write(&path, [format!("{start}{middle}end_header\n").into_bytes(), vec![0; body]].concat())
            .unwrap();
        let started = std::time::Instant::now();
        let cloud = ply::read_point_cloud(&path).expect("the file reads");
        assert_eq!(cloud.len(), 1);
        let elapsed = started.elapsed();
        assert!(elapsed.as_secs_f64() < 10.0, "{name}: {elapsed:?}");
    }
}

/// Parser text (`ParseIntError { kind: PosOverflow }`, "stream did not contain valid UTF-8")
/// and the values it quotes never reach users; the problem is said in words.
#[test]
fn parser_errors_are_said_in_words_without_quoting_the_file() {
    let header = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nproperty uchar red\nend_header\n";
    let error = cloud_error("overflow.ply", format!("{header}1 2 3 999\n").as_bytes());
    assert!(error.contains("entry 0") && error.contains("does not fit"), "{error}");
    assert!(!error.contains("ParseIntError") && !error.contains("999"), "{error}");
    let error = cloud_error(
        "latin1.ply",
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\xff\nend_header\n",
    );
    assert!(error.contains("not UTF-8 text") && !error.contains("stream did not"), "{error}");
}
