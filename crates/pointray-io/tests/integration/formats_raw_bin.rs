//! Raw `.bin` sweeps: KITTI's 4-float and nuScenes' 5-float records each read right, a
//! file that fits neither layout (or not the one its name implies) is refused with what
//! each layout makes of it, and a column spec overrides the name.

use std::path::PathBuf;

use glam::DVec3;
use pointray_io::formats::ColumnSpec;
use pointray_io::formats::detect::{PointFormat, detect_format};
use pointray_io::formats::raw_bin::read_raw_bin;
use pointray_io::formats::{read_point_cloud, read_point_cloud_with};

fn write_floats(name: &str, values: &[f32]) -> (tempfile::TempDir, PathBuf) {
    let bytes: Vec<u8> = values.iter().flat_map(|value| value.to_le_bytes()).collect();
    write_bytes(name, &bytes)
}

fn write_bytes(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

/// A nuScenes-like sweep of `count` points from a roof-mounted sensor: the ground lies below
/// it (negative z), rings run over 32 beams.
fn nuscenes_records(count: usize) -> Vec<[f32; 5]> {
    (0..count)
        .map(|i| {
            let angle = i as f32 * 0.1;
            let range = 5.0 + (i % 32) as f32;
            [
                range * angle.cos(),
                range * angle.sin(),
                -1.8 + 0.01 * (i % 7) as f32,
                (i % 100) as f32,
                (i % 32) as f32,
            ]
        })
        .collect()
}

fn kitti_records(count: usize) -> Vec<[f32; 4]> {
    nuscenes_records(count).iter().map(|r| [r[0], r[1], r[2], r[3] / 255.0]).collect()
}

#[test]
fn a_kitti_file_reads_four_floats_a_point_with_the_sensor_at_the_origin() {
    let records = [[1.5, -2.25, 0.125, 0.0], [10.0, 20.0, -1.0, 0.5], [-3.0, 4.0, 5.0, 1.0]];
    let (_dir, path) = write_floats("000000.bin", records.as_flattened());
    assert_eq!(detect_format(&path).unwrap(), PointFormat::RawBin);
    let cloud = read_point_cloud(&path).unwrap();
    let expected: Vec<DVec3> =
        records.iter().map(|r| DVec3::new(r[0].into(), r[1].into(), r[2].into())).collect();
    assert_eq!(cloud.positions, expected);
    assert_eq!(cloud.intensities, Some(vec![0.0, 0.5, 1.0]));
    assert_eq!(cloud.sensor_position, Some(DVec3::ZERO));
    assert_eq!((cloud.colors, cloud.rings), (None, None));
}

#[test]
fn a_nuscenes_sweep_reads_five_floats_a_point_with_rings() {
    // 80 points: 1600 bytes, a whole number of 16-byte records too, as in real sweeps.
    let records = nuscenes_records(80);
    let (_dir, path) = write_floats("n008__LIDAR_TOP__1533151603547590.pcd.bin", records.as_flattened());
    let cloud = read_point_cloud(&path).unwrap();
    assert_eq!(cloud.len(), 80);
    for (read, record) in cloud.positions.iter().zip(&records) {
        assert_eq!(*read, DVec3::new(record[0].into(), record[1].into(), record[2].into()));
    }
    let rings = cloud.rings.unwrap();
    assert_eq!(rings, records.iter().map(|r| r[4] as u16).collect::<Vec<_>>());
    let intensities = cloud.intensities.unwrap();
    assert!((intensities[79] - 79.0 / 255.0).abs() < 1e-6, "0-255 intensities are scaled");
    assert_eq!(cloud.sensor_position, Some(DVec3::ZERO));
}

#[test]
fn eight_bit_reflectance_is_normalised() {
    let (_dir, path) = write_floats("eight_bit.bin", &[0.0, 0.0, 1.0, 255.0, 0.0, 1.0, 0.0, 51.0]);
    assert_eq!(read_raw_bin(&path, None).unwrap().intensities, Some(vec![1.0, 0.2]));
}

fn refusal(name: &str, bytes: &[u8], columns: Option<&str>) -> String {
    let (_dir, path) = write_bytes(name, bytes);
    let spec = columns.map(|text| ColumnSpec::parse(text).unwrap());
    let message =
        read_point_cloud_with(&path, spec.as_ref()).expect_err("a file that does not fit must not read");
    let message = message.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    message
}

fn bytes_of(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|value| value.to_le_bytes()).collect()
}

#[test]
fn a_nuscenes_sweep_named_like_kitti_is_refused_not_misread() {
    // The trap: 5-float records whose length is also a whole number of 4-float ones.
    let message = refusal("sweep.bin", &bytes_of(nuscenes_records(80).as_flattened()), None);
    assert!(message.contains("does not read as KITTI"), "{message}");
    assert!(message.contains("negative or non-finite intensity"), "{message}");
    assert!(message.contains("it does read as nuScenes"), "{message}");
    assert!(message.contains("--columns"), "{message}");
}

#[test]
fn a_kitti_file_named_like_nuscenes_is_refused_not_misread() {
    let message = refusal("sweep.pcd.bin", &bytes_of(kitti_records(80).as_flattened()), None);
    assert!(message.contains("does not read as nuScenes"), "{message}");
    assert!(message.contains("ring that is not a whole number"), "{message}");
    assert!(message.contains("it does read as KITTI"), "{message}");
}

#[test]
fn a_file_that_fits_neither_layout_is_refused_with_both_reasons() {
    let message = refusal("odd.bin", &[0u8; 36], None);
    assert!(message.contains("length 36 is not a multiple of 16"), "{message}");
    assert!(message.contains("nor as nuScenes"), "{message}");
    assert!(message.contains("length 36 is not a multiple of 20"), "{message}");

    let garbage = bytes_of(&[1.0, 2.0, 3.0, -4.0, 0.5, 1.0, 2.0, 3.0, -4.0, 0.5]);
    let message = refusal("garbage.bin", &garbage, None);
    assert!(message.contains("does not read as KITTI") && message.contains("nor as nuScenes"), "{message}");
}

#[test]
fn a_column_spec_overrides_the_name() {
    let records = nuscenes_records(40);
    let (_dir, path) = write_floats("sweep.bin", records.as_flattened());
    let spec = ColumnSpec::parse("x,y,z,intensity,ring").unwrap();
    let cloud = read_point_cloud_with(&path, Some(&spec)).unwrap();
    assert_eq!(cloud.len(), 40);
    assert_eq!(cloud.rings.unwrap()[33], 1);

    // Another sensor's layout: x y z, a time column to skip, a classification.
    let values = [1.0, 2.0, 3.0, 0.25, 6.0, 4.0, 5.0, 6.0, 0.5, 2.0];
    let (_dir, path) = write_floats("custom.bin", &values);
    let spec = ColumnSpec::parse("x,y,z,_,classification").unwrap();
    let cloud = read_point_cloud_with(&path, Some(&spec)).unwrap();
    assert_eq!(cloud.positions, vec![DVec3::new(1.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 6.0)]);
    assert_eq!(cloud.classifications, Some(vec![6, 2]));
    assert_eq!(cloud.intensities, None);
}

#[test]
fn a_column_spec_is_checked_against_the_file() {
    let message = refusal("short.bin", &[0u8; 24], Some("x,y,z,intensity,ring"));
    assert!(
        message.contains("with columns x,y,z,intensity,ring: length 24 is not a multiple of 20"),
        "{message}"
    );
    let message = refusal("ring.bin", &bytes_of(&[0.0, 0.0, 0.0, 1.0, 2.5]), Some("x,y,z,intensity,ring"));
    assert!(message.contains("point 0: ring 2.5 is not a whole number"), "{message}");
}

#[test]
fn a_column_spec_is_refused_for_a_format_that_names_its_fields() {
    let header = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nend_header\n0 0 0\n";
    let message = refusal("named.ply", header.as_bytes(), Some("x,y,z"));
    assert!(message.contains("PLY file, which names its own fields"), "{message}");
}

#[test]
fn non_finite_coordinates_are_refused() {
    let mut values = [0.0f32; 8];
    values[4] = f32::NAN;
    let message = refusal("nan.bin", &bytes_of(&values), None);
    assert!(message.contains("point 1 has a non-finite coordinate"), "{message}");
    let message = refusal("inf.bin", &bytes_of(&[0.0, 0.0, f32::INFINITY, 0.0]), Some("x,y,z,i"));
    assert!(message.contains("point 0: non-finite coordinate"), "{message}");
}

#[test]
fn missing_file_is_an_os_error_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("absent.bin");
    let message = read_raw_bin(&path, None).unwrap_err().to_string();
    assert!(message.contains("absent.bin"), "{message}");
}
