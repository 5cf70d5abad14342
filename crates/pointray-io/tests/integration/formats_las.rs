//! LAS/LAZ reader: round trips through the `las` crate's writer, geo-coordinate precision,
//! malformed files, and the real Autzen tile.

use std::path::{Path, PathBuf};

use las::point::{Classification, Format};
use las::{Builder, Color, Point, Transform, Vector, Writer};
use pointray_io::IoError;
use pointray_io::formats::detect::{PointFormat, detect_format};
use pointray_io::formats::las::read_las;

/// Coordinates near 10^6 feet, stored at 0.01 resolution, as in geo-referenced tiles.
const SCALE: f64 = 0.01;
const EASTING: f64 = 1_234_567.89;
const NORTHING: f64 = 987_654.32;

fn geo_points() -> Vec<Point> {
    (0..50)
        .map(|i| Point {
            x: EASTING + f64::from(i) * 0.37,
            y: NORTHING - f64::from(i) * 0.11,
            z: 412.05 + f64::from(i) * 0.01,
            intensity: (i * 1000) as u16,
            color: Some(Color::new(i as u16 * 1000, 65535 - i as u16 * 1000, 32768)),
            gps_time: Some(f64::from(i)),
            classification: Classification::new([1, 2, 3, 5, 6, 9, 17][i as usize % 7]).unwrap(),
            ..Point::default()
        })
        .collect()
}

fn write_las(path: &Path, format: u8, compressed: bool, points: &[Point]) {
    let mut builder = Builder::from((1, 4));
    builder.point_format = Format::new(format).unwrap();
    builder.point_format.is_compressed = compressed;
    let transform = Transform { scale: SCALE, offset: 0.0 };
    builder.transforms = Vector { x: transform, y: transform, z: transform };
    let mut writer = Writer::from_path(path, builder.into_header().unwrap()).unwrap();
    for point in points {
        writer.write_point(point.clone()).unwrap();
    }
    writer.close().unwrap();
}

fn assert_same_points(path: &Path, points: &[Point], expect_color: bool) {
    let cloud = read_las(path).unwrap();
    assert_eq!(cloud.len(), points.len());
    for (read, written) in cloud.positions.iter().zip(points) {
        // The file stores integers of 0.01: the read value is within half a step.
        assert!((read.x - written.x).abs() <= SCALE / 2.0 + 1e-9, "{} vs {}", read.x, written.x);
        assert!((read.y - written.y).abs() <= SCALE / 2.0 + 1e-9);
        assert!((read.z - written.z).abs() <= SCALE / 2.0 + 1e-9);
    }
    let intensities = cloud.intensities.expect("intensities were written");
    for (read, written) in intensities.iter().zip(points) {
        assert!((read - f32::from(written.intensity) / 65535.0).abs() < 1e-6);
    }
    let classes: Vec<u8> = points.iter().map(|p| u8::from(p.classification)).collect();
    assert_eq!(cloud.classifications, Some(classes), "the ASPRS codes as written");
    match (cloud.colors, expect_color) {
        (Some(colors), true) => {
            for (read, written) in colors.iter().zip(points) {
                let c = written.color.unwrap();
                assert_eq!(*read, [(c.red >> 8) as u8, (c.green >> 8) as u8, (c.blue >> 8) as u8]);
            }
        }
        (None, false) => {}
        (colors, _) => panic!("colours {colors:?}, expected present = {expect_color}"),
    }
}

#[test]
fn las_round_trip_keeps_geo_coordinates_colours_and_intensities() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("geo.las");
    let points = geo_points();
    write_las(&path, 3, false, &points);
    assert_same_points(&path, &points, true);
    assert_eq!(detect_format(&path).unwrap(), PointFormat::Las);
}

#[test]
fn las_positions_keep_centimetres_at_a_million_feet() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("precision.las");
    let points = geo_points();
    write_las(&path, 3, false, &points);
    let cloud = read_las(&path).unwrap();
    // f32 would round 1.2 million to 0.125; f64 keeps neighbouring points 0.37 apart.
    let step = cloud.positions[1].x - cloud.positions[0].x;
    assert!((step - 0.37).abs() < 1e-6, "step {step}");
}

#[test]
fn laz_round_trip_matches_the_written_points() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("geo.laz");
    let points = geo_points();
    write_las(&path, 3, true, &points);
    assert_eq!(detect_format(&path).unwrap(), PointFormat::Laz);
    assert_same_points(&path, &points, true);
}

#[test]
fn las_1_4_format_6_has_no_colours() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("format6.las");
    let points: Vec<Point> = geo_points().into_iter().map(|p| Point { color: None, ..p }).collect();
    write_las(&path, 6, false, &points);
    assert_same_points(&path, &points, false);
}

#[test]
fn classes_all_zero_mean_never_classified() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("unclassified.las");
    let points: Vec<Point> = geo_points()
        .into_iter()
        .map(|p| Point { classification: Classification::new(0).unwrap(), ..p })
        .collect();
    write_las(&path, 3, false, &points);
    assert_eq!(read_las(&path).unwrap().classifications, None);
}

// ---- malformed files ----

fn valid_las_bytes() -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("valid.las");
    write_las(&path, 3, false, &geo_points());
    std::fs::read(path).unwrap()
}

/// Writes `bytes` to a file named `name`, reads it, and returns the error (the directory
/// lives as long as the returned guard).
fn read_bytes(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf, IoError) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let error = read_las(&path).expect_err("a malformed file must not read");
    (dir, path, error)
}

fn assert_names_file(path: &Path, error: &IoError, needle: &str) {
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.to_lowercase().contains(&needle.to_lowercase()), "{message:?} lacks {needle:?}");
}

#[test]
fn empty_file_is_refused() {
    let (_dir, path, error) = read_bytes("empty.las", &[]);
    assert_names_file(&path, &error, "LAS");
}

#[test]
fn wrong_signature_is_refused() {
    let mut bytes = valid_las_bytes();
    bytes[..4].copy_from_slice(b"LASX");
    let (_dir, path, error) = read_bytes("signature.las", &bytes);
    assert_names_file(&path, &error, "signature");
}

#[test]
fn truncated_point_data_is_refused() {
    let mut bytes = valid_las_bytes();
    bytes.truncate(bytes.len() - 10);
    let (_dir, path, error) = read_bytes("truncated.las", &bytes);
    assert_names_file(&path, &error, "truncated");
}

#[test]
fn truncated_header_is_refused() {
    let bytes = valid_las_bytes();
    let (_dir, path, error) = read_bytes("header.las", &bytes[..60]);
    assert_names_file(&path, &error, "LAS");
}

#[test]
fn unknown_point_format_is_unsupported_and_says_so() {
    let mut bytes = valid_las_bytes();
    bytes[104] = 42;
    let (_dir, path, error) = read_bytes("format42.las", &bytes);
    assert!(matches!(error, IoError::Unsupported { .. }), "{error}");
    assert_names_file(&path, &error, "point format 42");
    assert!(error.to_string().contains("supported: LAS 1.0-1.4"));
}

#[test]
fn unknown_version_is_unsupported() {
    let mut bytes = valid_las_bytes();
    bytes[24] = 2; // major version
    let (_dir, path, error) = read_bytes("version2.las", &bytes);
    assert!(matches!(error, IoError::Unsupported { .. }), "{error}");
    assert_names_file(&path, &error, "LAS version 2.4");
}

#[test]
fn more_declared_points_than_stored_is_refused() {
    let mut bytes = valid_las_bytes();
    // The legacy 32-bit count (offset 107) and the LAS 1.4 64-bit count (offset 247).
    bytes[107..111].copy_from_slice(&4_000_000_000u32.to_le_bytes());
    bytes[247..255].copy_from_slice(&4_000_000_000u64.to_le_bytes());
    let (_dir, path, error) = read_bytes("count.las", &bytes);
    assert_names_file(&path, &error, "LAS");
}

// ---- the real tile ----

#[test]
fn autzen_tile_reads_with_its_point_count_colours_and_bounds() {
    let data = pointray_test_support::data_dir();
    let cloud = read_las(&data.join("scans/autzen_trim.las")).unwrap();
    assert_eq!(cloud.len(), 110_000);
    let colors = cloud.colors.as_ref().expect("autzen has RGB");
    assert_eq!(colors.len(), 110_000);
    let distinct: std::collections::HashSet<_> = colors.iter().take(5000).collect();
    assert!(distinct.len() > 50, "colours look constant: {} distinct", distinct.len());
    let classes = cloud.classifications.as_ref().expect("autzen is classified");
    let ground = classes.iter().filter(|&&class| class == 2).count();
    assert_eq!((ground, classes.len() - ground), (26_107, 83_893), "ground (2) and unclassified (1)");
    assert!(classes.iter().all(|&class| class == 1 || class == 2));
    let (min, max) = cloud
        .positions
        .iter()
        .fold((cloud.positions[0], cloud.positions[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    // State-plane feet: eastings and northings near 10^6, a tile of a few thousand feet,
    // terrain and buildings a few hundred feet high.
    assert!(min.x > 1e5 && max.x < 1e7 && min.y > 1e5 && max.y < 1e7, "{min} {max}");
    let extent = max - min;
    assert!(extent.x > 100.0 && extent.x < 20_000.0 && extent.y > 100.0 && extent.y < 20_000.0, "{extent}");
    assert!(extent.z > 10.0 && extent.z < 2_000.0, "{extent}");
}

#[test]
fn laz_chunk_count_beyond_the_file_is_refused_before_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("valid.laz");
    write_las(&path, 3, true, &geo_points());
    let mut bytes = std::fs::read(&path).unwrap();
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let data_start = word(96);
    let table = i64::from_le_bytes(bytes[data_start..data_start + 8].try_into().unwrap()) as usize;
    bytes[table + 4..table + 8].copy_from_slice(&u32::MAX.to_le_bytes());
    let (_dir, path, error) = read_bytes("chunks.laz", &bytes);
    assert_names_file(&path, &error, "chunk table declares 4294967295 chunks");
}

#[test]
fn laz_without_point_items_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("valid.laz");
    write_las(&path, 3, true, &geo_points());
    let mut bytes = std::fs::read(&path).unwrap();
    // The LASzip VLR: a 54-byte header whose user id starts 2 bytes in, then the item
    // count 32 bytes into its data.
    let user_id = bytes.windows(14).position(|w| w == b"laszip encoded").unwrap();
    let count_at = user_id - 2 + 54 + 32;
    bytes[count_at..count_at + 2].copy_from_slice(&0u16.to_le_bytes());
    let (_dir, path, error) = read_bytes("items.laz", &bytes);
    assert_names_file(&path, &error, "describes no point items");
}

#[test]
fn evlr_longer_than_the_file_is_refused_before_allocating() {
    let mut bytes = valid_las_bytes();
    // Point the LAS 1.4 header at one EVLR, just past the points, claiming 3 GB of data.
    let evlr_at = bytes.len() as u64;
    bytes[235..243].copy_from_slice(&evlr_at.to_le_bytes());
    bytes[243..247].copy_from_slice(&1u32.to_le_bytes());
    let mut evlr = vec![0u8; 60];
    evlr[20..28].copy_from_slice(&3_000_000_000u64.to_le_bytes());
    bytes.extend(evlr);
    let (_dir, path, error) = read_bytes("evlr.las", &bytes);
    assert_names_file(&path, &error, "declares 3000000000 bytes");
}

/// A header whose scale or offset cannot place the points (a scale of 0 or 1e-300, an offset
/// of 1e300) used to collapse the cloud onto a plane; it is refused, naming the field.
#[test]
fn degenerate_scales_and_offsets_are_refused_by_field() {
    // The header's x, y and z scale factors start at byte 131, their offsets at 155.
    let cases: [(usize, f64, &str); 5] = [
        (131, 0.0, "x scale factor"),
        (131, 1e-300, "x scale factor"),
        (147, f64::NAN, "z scale factor"),
        (155, 1e300, "x offset"),
        (163, f64::INFINITY, "y offset"),
    ];
    for (at, value, field) in cases {
        let mut bytes = valid_las_bytes();
        bytes[at..at + 8].copy_from_slice(&value.to_le_bytes());
        let (_dir, path, error) = read_bytes("scaled.las", &bytes);
        assert_names_file(&path, &error, field);
    }
}

/// A LAS 1.4 count of 2^60 points in a small file was trusted by the streamed reader, which
/// sized a scratch file by it ("Invalid argument" on a temporary path); the count is checked
/// against the bytes the file holds when it is opened.
#[test]
fn a_count_beyond_the_files_bytes_is_refused_when_opened_to_stream() {
    let mut bytes = valid_las_bytes();
    // The legacy 32-bit count (offset 107) is 0 when the count needs more bits.
    bytes[107..111].copy_from_slice(&0u32.to_le_bytes());
    bytes[247..255].copy_from_slice(&(1u64 << 60).to_le_bytes());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("count.las");
    std::fs::write(&path, &bytes).unwrap();
    let budget = pointray_io::MemoryBudget { bytes: 1 << 30 };
    let error = pointray_io::PointStream::open(&path, None, budget).err().expect("refused").to_string();
    assert!(error.contains("count.las") && error.contains("1152921504606846976 points"), "{error}");
}
