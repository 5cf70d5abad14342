//! PCD reader: round trips through `pcd-rs`'s writer (ascii, binary, binary_compressed),
//! a hand-written file with PCL's packed colour, and malformed files.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use pcd_rs::{DataKind, DynRecord, Field};
use pointray_io::formats::detect::{PointFormat, detect_format};
use pointray_io::formats::pcd::read_pcd;
use pointray_io::{IoError, PointCloud};

use pointray_test_support::write_pcd_f32;

fn sample_records() -> Vec<DynRecord> {
    (0..40)
        .map(|i| {
            let f = i as f32;
            DynRecord(vec![
                Field::F32(vec![f * 0.5]),
                Field::F32(vec![-f]),
                Field::F32(vec![f * f * 0.01]),
                Field::F32(vec![f * 4.0]),
                Field::F32(vec![0.0]),
                Field::F32(vec![1.0]),
                Field::F32(vec![0.0]),
            ])
        })
        .collect()
}

fn write_pcd(path: &Path, data_kind: DataKind, records: Vec<DynRecord>) {
    let fields = ["x", "y", "z", "intensity", "normal_x", "normal_y", "normal_z"];
    write_pcd_f32(path, data_kind, &fields, records.into_iter());
}

fn assert_matches_sample(cloud: &PointCloud) {
    assert_eq!(cloud.len(), 40);
    for (i, position) in cloud.positions.iter().enumerate() {
        let f = i as f32;
        let expected = DVec3::new((f * 0.5).into(), (-f).into(), (f * f * 0.01).into());
        assert_eq!(*position, expected);
    }
    let intensities = cloud.intensities.as_ref().unwrap();
    // Raw 0..156 fits the 8-bit scale.
    assert!((intensities[10] - 40.0 / 255.0).abs() < 1e-6);
    assert!(cloud.normals.as_ref().unwrap().iter().all(|n| *n == Vec3::Y));
    assert!(cloud.colors.is_none());
}

fn round_trip(data_kind: DataKind) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.pcd");
    write_pcd(&path, data_kind, sample_records());
    assert_eq!(detect_format(&path).unwrap(), PointFormat::Pcd);
    assert_matches_sample(&read_pcd(&path).unwrap());
}

#[test]
fn ascii_round_trip() {
    round_trip(DataKind::Ascii);
}

#[test]
fn binary_round_trip() {
    round_trip(DataKind::Binary);
}

#[test]
fn binary_compressed_round_trip() {
    round_trip(DataKind::BinaryCompressed);
}

const PACKED_RGB_HEADER: &str = "# .PCD v0.7 - Point Cloud Data file format
VERSION 0.7
FIELDS x y z rgb
SIZE 4 4 4 4
TYPE F F F F
COUNT 1 1 1 1
WIDTH 3
HEIGHT 1
VIEWPOINT 0 0 0 1 0 0 0
POINTS 3
DATA ascii
";

#[test]
fn packed_float_rgb_unpacks_and_nan_points_are_dropped() {
    let red = f32::from_bits(0x00ff_0000);
    let teal = f32::from_bits(0x0000_8080);
    let text = format!("{PACKED_RGB_HEADER}1 2 3 {red:e}\nnan nan nan 0\n4 5 6 {teal:e}\n");
    let (_dir, path) = write_file("rgb.pcd", text.as_bytes());
    let cloud = read_pcd(&path).unwrap();
    assert_eq!(cloud.positions, vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0)]);
    assert_eq!(cloud.colors, Some(vec![[255, 0, 0], [0, 128, 128]]));
    assert_eq!(cloud.intensities, None);
}

// ---- malformed files ----

fn write_file(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

fn assert_refused(name: &str, bytes: &[u8], needle: &str) -> IoError {
    let (_dir, path) = write_file(name, bytes);
    let error = read_pcd(&path).expect_err("a malformed file must not read");
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
    error
}

fn valid_bytes(data_kind: DataKind) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("valid.pcd");
    write_pcd(&path, data_kind, sample_records());
    std::fs::read(path).unwrap()
}

#[test]
fn header_without_data_line_is_refused() {
    assert_refused("nodata.pcd", b"VERSION 0.7\nFIELDS x y z\n", "DATA");
}

#[test]
fn missing_z_field_is_refused() {
    let text = PACKED_RGB_HEADER.replace("FIELDS x y z rgb", "FIELDS x y w rgb");
    assert_refused("noz.pcd", text.as_bytes(), "no field \"z\"");
}

#[test]
fn half_float_field_is_unsupported() {
    let text = PACKED_RGB_HEADER.replace("SIZE 4 4 4 4", "SIZE 2 4 4 4");
    let error = assert_refused("half.pcd", text.as_bytes(), "not supported");
    assert!(matches!(error, IoError::Unsupported { .. }));
}

#[test]
fn truncated_binary_data_is_refused() {
    let mut bytes = valid_bytes(DataKind::Binary);
    bytes.truncate(bytes.len() - 3);
    assert_refused("truncated.pcd", &bytes, "needing");
}

#[test]
fn lying_compressed_sizes_are_refused() {
    let bytes = valid_bytes(DataKind::BinaryCompressed);
    let data_at = find(&bytes, b"binary_compressed\n") + b"binary_compressed\n".len();
    let mut lying = bytes.clone();
    lying[data_at + 4..data_at + 8].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_refused("compressed.pcd", &lying, "compressed block");
}

#[test]
fn ascii_row_with_missing_values_is_refused() {
    let text = format!("{PACKED_RGB_HEADER}1 2 3 0\n4 5\n6 7 8 0\n");
    assert_refused("short.pcd", text.as_bytes(), "PCD");
}

#[test]
fn vector_valued_position_is_unsupported() {
    let text = PACKED_RGB_HEADER.replace("COUNT 1 1 1 1", "COUNT 2 1 1 1");
    let error = assert_refused("count.pcd", text.as_bytes(), "COUNT 2");
    assert!(matches!(error, IoError::Unsupported { .. }));
}

fn find(haystack: &[u8], needle: &[u8]) -> usize {
    haystack.windows(needle.len()).position(|window| window == needle).unwrap()
}

const RING_HEADER: &str = "VERSION 0.7\nFIELDS x y z intensity ring\nSIZE 4 4 4 4 2\nTYPE F F F F U\n\
                           COUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 1.5 -2 0.5 1 0 0 0\nPOINTS 2\n";

#[test]
fn rings_and_a_viewpoint_are_read_in_ascii_and_binary() {
    let ascii = format!("{RING_HEADER}DATA ascii\n1 2 3 10 5\n4 5 6 20 31\n");
    let mut binary = format!("{RING_HEADER}DATA binary\n").into_bytes();
    for (position, intensity, ring) in [([1.0f32, 2.0, 3.0], 10.0f32, 5u16), ([4.0, 5.0, 6.0], 20.0, 31)] {
        position.iter().chain([&intensity]).for_each(|v| binary.extend(v.to_le_bytes()));
        binary.extend(ring.to_le_bytes());
    }
    for (name, bytes) in [("ascii.pcd", ascii.into_bytes()), ("binary.pcd", binary)] {
        let (_dir, path) = write_file(name, &bytes);
        let cloud = read_pcd(&path).unwrap();
        assert_eq!(cloud.positions, vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0)], "{name}");
        assert_eq!(cloud.rings, Some(vec![5, 31]), "{name}");
        assert_eq!(cloud.sensor_position, Some(DVec3::new(1.5, -2.0, 0.5)), "{name}");
    }
}

#[test]
fn the_default_viewpoint_says_nothing_about_a_sensor() {
    let text = format!("{PACKED_RGB_HEADER}1 2 3 0\n4 5 6 0\n6 7 8 0\n");
    let (_dir, path) = write_file("default.pcd", text.as_bytes());
    assert_eq!(read_pcd(&path).unwrap().sensor_position, None);
}

#[test]
fn rings_must_be_integers_in_range() {
    let float =
        RING_HEADER.replace("TYPE F F F F U", "TYPE F F F F F").replace("SIZE 4 4 4 4 2", "SIZE 4 4 4 4 4");
    let error = assert_refused(
        "float_ring.pcd",
        format!("{float}DATA ascii\n1 2 3 1 5\n4 5 6 1 6\n").as_bytes(),
        "ring",
    );
    assert!(matches!(error, IoError::Unsupported { .. }));
    let signed = RING_HEADER.replace("TYPE F F F F U", "TYPE F F F F I");
    assert_refused(
        "negative_ring.pcd",
        format!("{signed}DATA ascii\n1 2 3 1 5\n4 5 6 1 -1\n").as_bytes(),
        "point 1: ring -1 is outside 0 to 65535",
    );
}

#[test]
fn a_binary_header_over_a_text_body_is_refused() {
    let text = PACKED_RGB_HEADER.replace("DATA ascii", "DATA binary");
    let body = "1.5 2.5 3.5 4.5\n4.5 5.5 6.5 7.5\n6.5 7.5 8.5 9.5\n";
    assert_refused(
        "binary_text.pcd",
        format!("{text}{body}").as_bytes(),
        "says DATA binary, but the data is text",
    );
}

/// PCL and pypcd4 read the declared points of a binary file that has bytes after them (as
/// pypcd4's own `binary.pcd` does), and so does pointray, with a warning.
#[test]
fn binary_data_beyond_the_declared_points_is_left_out() {
    let valid = valid_bytes(DataKind::Binary);
    let (_dir, path) = write_file("valid.pcd", &valid);
    let expected = read_pcd(&path).unwrap();
    let mut bytes = valid;
    bytes.extend([0u8; 28]);
    let (_dir, path) = write_file("extra.pcd", &bytes);
    assert_eq!(read_pcd(&path).unwrap(), expected);
}

/// A field of several values a point that pointray reads as one (pypcd4's
/// `ascii_multi_count.pcd`: intensity with COUNT 4) is left out, not the whole file.
#[test]
fn a_multi_count_attribute_is_left_out_and_the_points_read() {
    let header = "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 4\n\
                  WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n";
    let text = format!("{header}0 0 1 0.1 0.1 0.1 0.1\n1 0 0 0.2 0.2 0.2 0.2\n");
    let (_dir, path) = write_file("multi.pcd", text.as_bytes());
    let cloud = read_pcd(&path).unwrap();
    assert_eq!(cloud.positions, vec![DVec3::new(0.0, 0.0, 1.0), DVec3::new(1.0, 0.0, 0.0)]);
    assert_eq!(cloud.intensities, None);
}

/// A header that is not text is said to be so, not in the standard library's words.
#[test]
fn a_header_that_is_not_text_is_said_to_be_so() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("latin1.pcd");
    std::fs::write(&path, b"VERSION .7\nFIELDS x y z\n\xff\xfe\n").unwrap();
    let error = pointray_io::formats::pcd::read_pcd(&path).unwrap_err().to_string();
    assert!(error.contains("latin1.pcd") && error.contains("not UTF-8 text"), "{error}");
    assert!(!error.contains("stream did not"), "{error}");
}
