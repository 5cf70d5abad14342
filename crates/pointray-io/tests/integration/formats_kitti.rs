//! KITTI `.bin` reader: round trip of hand-written records and malformed lengths.

use std::path::PathBuf;

use glam::DVec3;
use pointray_io::formats::detect::{PointFormat, detect_format};
use pointray_io::formats::kitti::read_kitti_bin;

fn write_records(name: &str, records: &[[f32; 4]]) -> (tempfile::TempDir, PathBuf) {
    let bytes: Vec<u8> = records.iter().flatten().flat_map(|value| value.to_le_bytes()).collect();
    write_bytes(name, &bytes)
}

fn write_bytes(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

#[test]
fn records_read_back_with_the_sensor_at_the_origin() {
    let records = [[1.5, -2.25, 0.125, 0.0], [10.0, 20.0, -1.0, 0.5], [-3.0, 4.0, 5.0, 1.0]];
    let (_dir, path) = write_records("000000.bin", &records);
    assert_eq!(detect_format(&path).unwrap(), PointFormat::KittiBin);
    let cloud = read_kitti_bin(&path).unwrap();
    let expected: Vec<DVec3> =
        records.iter().map(|r| DVec3::new(r[0].into(), r[1].into(), r[2].into())).collect();
    assert_eq!(cloud.positions, expected);
    assert_eq!(cloud.intensities, Some(vec![0.0, 0.5, 1.0]));
    assert_eq!(cloud.sensor_position, Some(DVec3::ZERO));
    assert_eq!(cloud.colors, None);
}

#[test]
fn eight_bit_reflectance_is_normalised() {
    let (_dir, path) = write_records("eight_bit.bin", &[[0.0, 0.0, 1.0, 255.0], [0.0, 1.0, 0.0, 51.0]]);
    assert_eq!(read_kitti_bin(&path).unwrap().intensities, Some(vec![1.0, 0.2]));
}

fn assert_refused(name: &str, bytes: &[u8], needle: &str) {
    let (_dir, path) = write_bytes(name, bytes);
    let message = read_kitti_bin(&path).expect_err("a malformed file must not read").to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
}

#[test]
fn length_not_a_multiple_of_sixteen_is_refused() {
    assert_refused("short.bin", &[0u8; 15], "not a multiple of 16");
}

#[test]
fn one_extra_byte_is_refused() {
    assert_refused("extra.bin", &[0u8; 33], "length 33");
}

#[test]
fn nan_coordinate_is_refused() {
    let mut bytes = vec![0u8; 32];
    bytes[16..20].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_refused("nan.bin", &bytes, "point 1 has a non-finite coordinate");
}

#[test]
fn infinite_coordinate_is_refused() {
    let mut bytes = vec![0u8; 16];
    bytes[8..12].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_refused("inf.bin", &bytes, "point 0 has a non-finite coordinate");
}

#[test]
fn missing_file_is_an_os_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent.bin");
    let message = read_kitti_bin(&path).unwrap_err().to_string();
    assert!(message.contains("absent.bin"), "{message}");
}
