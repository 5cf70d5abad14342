//! E57 reader: round trips through the `e57` crate's writer, with scan poses, several
//! scans merged, and malformed files.

use std::path::{Path, PathBuf};

use e57::{E57Writer, Quaternion, Record, RecordDataType, RecordName, RecordValue, Transform, Translation};
use glam::{DQuat, DVec3};
use pointray_io::IoError;
use pointray_io::formats::detect::{PointFormat, detect_format};
use pointray_io::formats::e57::read_e57;

/// One scan to write: its pose, its local points, whether it carries colour, and the number
/// of rows of its angular grid (point `i` lies on row `i % rows`), if it has one.
struct Scan {
    rotation: DQuat,
    translation: DVec3,
    points: Vec<DVec3>,
    with_color: bool,
    rows: Option<i64>,
}

fn prototype(with_color: bool, rows: Option<i64>) -> Vec<Record> {
    let double = |name| Record { name, data_type: RecordDataType::Double { min: None, max: None } };
    let integer = |name, max| Record { name, data_type: RecordDataType::Integer { min: 0, max } };
    let mut records = vec![
        double(RecordName::CartesianX),
        double(RecordName::CartesianY),
        double(RecordName::CartesianZ),
        integer(RecordName::Intensity, 1000),
    ];
    if with_color {
        records.extend(
            [RecordName::ColorRed, RecordName::ColorGreen, RecordName::ColorBlue].map(|n| integer(n, 255)),
        );
    }
    if let Some(rows) = rows {
        records.extend([integer(RecordName::RowIndex, rows - 1), integer(RecordName::ColumnIndex, 1000)]);
    }
    records
}

fn write_e57(path: &Path, scans: &[Scan]) {
    let mut writer = E57Writer::from_file(path, "file-guid").unwrap();
    for (index, scan) in scans.iter().enumerate() {
        let mut cloud =
            writer.add_pointcloud(&format!("scan-{index}"), prototype(scan.with_color, scan.rows)).unwrap();
        let q = scan.rotation;
        let t = scan.translation;
        cloud.set_transform(Some(Transform {
            rotation: Quaternion { w: q.w, x: q.x, y: q.y, z: q.z },
            translation: Translation { x: t.x, y: t.y, z: t.z },
        }));
        for (i, p) in scan.points.iter().enumerate() {
            let mut values = vec![
                RecordValue::Double(p.x),
                RecordValue::Double(p.y),
                RecordValue::Double(p.z),
                RecordValue::Integer(i as i64 * 100),
            ];
            if scan.with_color {
                values.extend([
                    RecordValue::Integer(255),
                    RecordValue::Integer(i as i64),
                    RecordValue::Integer(0),
                ]);
            }
            if let Some(rows) = scan.rows {
                values.extend([RecordValue::Integer(i as i64 % rows), RecordValue::Integer(i as i64 / rows)]);
            }
            cloud.add_point(values).unwrap();
        }
        cloud.finalize().unwrap();
    }
    writer.finalize().unwrap();
}

fn two_scans(second_has_color: bool) -> Vec<Scan> {
    let local = |n: usize| (0..n).map(|i| DVec3::new(i as f64, 2.0 * i as f64, 0.5)).collect::<Vec<_>>();
    vec![
        Scan {
            rotation: DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
            translation: DVec3::new(10.0, 20.0, 30.0),
            points: local(8),
            with_color: true,
            rows: Some(3),
        },
        Scan {
            rotation: DQuat::IDENTITY,
            translation: DVec3::new(-5.0, 0.0, 1.0),
            points: local(5),
            with_color: second_has_color,
            rows: Some(4),
        },
    ]
}

#[test]
fn scans_are_posed_merged_and_the_first_pose_is_the_sensor() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scans.e57");
    let scans = two_scans(true);
    write_e57(&path, &scans);
    assert_eq!(detect_format(&path).unwrap(), PointFormat::E57);

    let cloud = read_e57(&path).unwrap();
    let expected: Vec<DVec3> = scans
        .iter()
        .flat_map(|scan| scan.points.iter().map(|p| scan.rotation * *p + scan.translation))
        .collect();
    assert_eq!(cloud.len(), expected.len());
    for (read, want) in cloud.positions.iter().zip(&expected) {
        assert!(read.distance(*want) < 1e-9, "{read} vs {want}");
    }
    assert_eq!(cloud.sensor_position, Some(DVec3::new(10.0, 20.0, 30.0)));
    let colors = cloud.colors.unwrap();
    assert_eq!(colors[3], [255, 3, 0]);
    assert_eq!(colors[8 + 4], [255, 4, 0]);
    let intensities = cloud.intensities.unwrap();
    assert!((intensities[5] - 0.5).abs() < 1e-6, "{}", intensities[5]);
    assert_eq!(cloud.rings, Some(vec![0, 1, 2, 0, 1, 2, 0, 1, 0, 1, 2, 3, 0]), "row indices");
    let stations = [DVec3::new(10.0, 20.0, 30.0), DVec3::new(-5.0, 0.0, 1.0)];
    let expected_origins: Vec<DVec3> = (0..13).map(|i| stations[usize::from(i >= 8)]).collect();
    assert_eq!(cloud.sensor_origins, Some(expected_origins), "each point's own scan station");
}

#[test]
fn one_scan_has_one_sensor_position_and_rows_only_when_every_scan_has_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one.e57");
    let mut scans = two_scans(true);
    scans.truncate(1);
    write_e57(&path, &scans);
    let cloud = read_e57(&path).unwrap();
    assert_eq!((cloud.sensor_position, cloud.sensor_origins), (Some(DVec3::new(10.0, 20.0, 30.0)), None));

    let mut scans = two_scans(true);
    scans[1].rows = None;
    write_e57(&path, &scans);
    assert_eq!(read_e57(&path).unwrap().rings, None);
}

#[test]
fn colours_are_dropped_when_one_scan_lacks_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mixed.e57");
    write_e57(&path, &two_scans(false));
    let cloud = read_e57(&path).unwrap();
    assert_eq!(cloud.len(), 13);
    assert_eq!(cloud.colors, None);
    assert_eq!(cloud.intensities.map(|i| i.len()), Some(13));
}

// ---- malformed files ----

fn valid_bytes() -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("valid.e57");
    write_e57(&path, &two_scans(true));
    std::fs::read(path).unwrap()
}

fn assert_refused(name: &str, bytes: &[u8], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path: PathBuf = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let error: IoError = read_e57(&path).expect_err("a malformed file must not read");
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(needle), "{message:?} lacks {needle:?}");
}

#[test]
fn empty_file_is_refused() {
    assert_refused("empty.e57", &[], "shorter than");
}

#[test]
fn wrong_signature_is_refused() {
    let mut bytes = valid_bytes();
    bytes[..8].copy_from_slice(b"ASTM-E58");
    assert_refused("signature.e57", &bytes, "signature");
}

#[test]
fn truncated_file_is_refused() {
    let bytes = valid_bytes();
    assert_refused("truncated.e57", &bytes[..bytes.len() / 2], "E57");
}

#[test]
fn xml_length_beyond_the_file_is_refused() {
    let mut bytes = valid_bytes();
    bytes[32..40].copy_from_slice(&(1u64 << 40).to_le_bytes());
    assert_refused("xml.e57", &bytes, "XML at");
}

#[test]
fn corrupted_page_fails_its_checksum() {
    let mut bytes = valid_bytes();
    bytes[100] ^= 0xff;
    assert_refused("crc.e57", &bytes, "E57");
}

#[test]
fn header_alone_is_refused() {
    let bytes = valid_bytes();
    assert_refused("header.e57", &bytes[..48], "E57");
}
