//! The points file has exactly the fixed layout, byte for byte, and pointray reads it back.

use glam::DVec3;
use pointray_lidar::ply_output::{RECORD_BYTES, write_returns};
use pointray_lidar::{Classification, Return};

fn sample_returns() -> Vec<Return> {
    (0..3)
        .map(|i| Return {
            position: DVec3::new(1000.5 + f64::from(i), -2.25, 0.125),
            intensity: 0.25 * i as f32,
            ring: 60 + i as u16,
            azimuth: 1.5,
            time: 0.05,
            classification: Classification::VEHICLE,
            sensor: DVec3::new(0.0, 0.5, 1.73),
        })
        .collect()
}

#[test]
fn the_header_and_records_are_the_fixed_layout() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scan.ply");
    let returns = sample_returns();
    write_returns(&path, &returns, &["pointray scan\nof a test".into()]).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let header = "ply\nformat binary_little_endian 1.0\ncomment pointray scan of a test\nelement vertex 3\n\
        property double x\nproperty double y\nproperty double z\nproperty float intensity\n\
        property ushort ring\nproperty float azimuth\nproperty float time\nproperty uchar classification\n\
        property double sensor_x\nproperty double sensor_y\nproperty double sensor_z\nend_header\n";
    assert_eq!(std::str::from_utf8(&bytes[..header.len()]).unwrap(), header);
    assert_eq!(bytes.len(), header.len() + 3 * RECORD_BYTES);

    let record = &bytes[header.len() + RECORD_BYTES..header.len() + 2 * RECORD_BYTES];
    let f64_at = |at: usize| f64::from_le_bytes(record[at..at + 8].try_into().unwrap());
    let f32_at = |at: usize| f32::from_le_bytes(record[at..at + 4].try_into().unwrap());
    assert_eq!([f64_at(0), f64_at(8), f64_at(16)], [1001.5, -2.25, 0.125]);
    assert_eq!(f32_at(24), 0.25);
    assert_eq!(u16::from_le_bytes([record[28], record[29]]), 61);
    assert_eq!([f32_at(30), f32_at(34)], [1.5, 0.05]);
    assert_eq!(record[38], 64);
    assert_eq!([f64_at(39), f64_at(47), f64_at(55)], [0.0, 0.5, 1.73]);

    let cloud = pointray_io::formats::read_point_cloud(&path).unwrap();
    assert_eq!(cloud.positions, returns.iter().map(|r| r.position).collect::<Vec<_>>());
}

#[test]
fn a_non_finite_return_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scan.ply");
    let mut returns = sample_returns();
    returns[2].position.y = f64::NAN;
    let error = write_returns(&path, &returns, &[]).unwrap_err().to_string();
    assert!(error.contains("scan.ply") && error.contains("return 2"), "{error}");
    assert!(!path.exists());
}
