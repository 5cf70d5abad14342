//! Clouds read in chunks are the clouds a whole read gives, attribute scaling included;
//! files that cannot be chunked are read whole within the budget and refused beyond it.

use std::path::Path;

use glam::{DVec3, Vec3};
use las::point::{Classification, Format};
use las::{Builder, Color, Point, Transform, Vector, Writer};
use pointray_io::formats::ply::{PlyEncoding, write_point_cloud_as};
use pointray_io::formats::read_point_cloud;
use pointray_io::{IoError, MemoryBudget, PointCloud, PointStream};

const PLENTY: MemoryBudget = MemoryBudget { bytes: 1 << 30 };

fn chunked(path: &Path, chunk: usize) -> PointCloud {
    let mut stream = PointStream::open(path, None, PLENTY).unwrap();
    assert!(stream.is_chunked(), "{path:?} is chunked");
    let mut surveyed = Vec::new();
    stream
        .survey(chunk, |positions| {
            assert!(positions.len() <= chunk);
            surveyed.extend_from_slice(positions);
            Ok::<(), IoError>(())
        })
        .unwrap();
    let mut whole: Option<PointCloud> = None;
    stream
        .read(chunk, |part| {
            match whole.as_mut() {
                Some(whole) => whole.append(part),
                None => whole = Some(part),
            }
            Ok::<(), IoError>(())
        })
        .unwrap();
    let whole = whole.unwrap_or_default();
    assert_eq!(surveyed, whole.positions, "both passes see the same positions");
    assert_eq!(stream.len(), whole.len() as u64);
    whole
}

fn attributed_cloud(count: usize) -> PointCloud {
    let positions: Vec<DVec3> =
        (0..count).map(|i| DVec3::new(i as f64 * 0.5, (i % 7) as f64, 1e6 + (i % 3) as f64)).collect();
    PointCloud {
        normals: Some((0..count).map(|i| Vec3::new(0.0, (i % 2) as f32, 1.0)).collect()),
        colors: Some((0..count).map(|i| [i as u8, 255 - i as u8, 7]).collect()),
        intensities: Some((0..count).map(|i| i as f32 * 0.01).collect()),
        rings: Some((0..count).map(|i| (i % 64) as u16).collect()),
        classifications: Some((0..count).map(|i| (i % 5) as u8).collect()),
        sensor_origins: Some(vec![DVec3::new(1.0, 2.0, 3.0); count]),
        ..PointCloud::from_positions(positions)
    }
}

#[test]
fn binary_ply_in_chunks_reads_as_a_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.ply");
    write_point_cloud_as(&path, &attributed_cloud(301), PlyEncoding::BinaryLittleEndian).unwrap();
    let whole = read_point_cloud(&path).unwrap();
    assert!(
        whole.intensities.as_ref().unwrap().iter().any(|&v| v < 1.0),
        "intensities scaled by the largest"
    );
    assert_eq!(chunked(&path, 64), whole);
    assert_eq!(chunked(&path, 1000), whole);
}

#[test]
fn a_chunked_ply_names_the_files_bad_point() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.ply");
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n\
                      property float y\nproperty float z\nend_header\n"
        .to_vec();
    for i in 0..100 {
        let y = if i == 77 { f32::NAN } else { (i % 9) as f32 };
        [i as f32, y, 0.5].iter().for_each(|v| bytes.extend(v.to_le_bytes()));
    }
    std::fs::write(&path, bytes).unwrap();
    let mut stream = PointStream::open(&path, None, PLENTY).unwrap();
    let error = stream.survey(10, |_| Ok::<(), IoError>(())).unwrap_err().to_string();
    assert!(error.contains("cloud.ply") && error.contains("point 77 "), "{error}");
}

#[test]
fn a_truncated_ply_is_refused_before_any_chunk() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.ply");
    write_point_cloud_as(&path, &attributed_cloud(50), PlyEncoding::BinaryLittleEndian).unwrap();
    let length = std::fs::metadata(&path).unwrap().len();
    std::fs::OpenOptions::new().write(true).open(&path).unwrap().set_len(length - 10).unwrap();
    let error = PointStream::open(&path, None, PLENTY).err().expect("refused").to_string();
    assert!(error.contains("cloud.ply") && error.contains("truncated"), "{error}");
}

#[test]
fn laz_in_chunks_reads_as_a_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.laz");
    let mut builder = Builder::from((1, 4));
    builder.point_format = Format::new(3).unwrap();
    builder.point_format.is_compressed = true;
    let transform = Transform { scale: 0.01, offset: 0.0 };
    builder.transforms = Vector { x: transform, y: transform, z: transform };
    let mut writer = Writer::from_path(&path, builder.into_header().unwrap()).unwrap();
    for i in 0..500u16 {
        writer
            .write_point(Point {
                x: 1e5 + f64::from(i) * 0.3,
                y: f64::from(i % 17),
                z: 2.0,
                intensity: i * 3,
                color: Some(Color::new(i, 2 * i, 300)),
                gps_time: Some(0.0),
                classification: Classification::new((i % 3) as u8).unwrap(),
                ..Point::default()
            })
            .unwrap();
    }
    writer.close().unwrap();
    let whole = read_point_cloud(&path).unwrap();
    assert_eq!(chunked(&path, 37), whole);
}

#[test]
fn copc_in_chunks_reads_as_a_whole() {
    let path = pointray_test_support::data_file("scans/autzen_trim.copc.laz");
    let whole = read_point_cloud(&path).unwrap();
    // Smaller than most of its chunks, and larger than several together.
    for chunk in [997, 40_000] {
        assert_eq!(chunked(&path, chunk), whole, "chunks of {chunk}");
    }
}

/// The points a read of `stream` in chunks of `chunk` hands out.
fn points_read(stream: &mut PointStream, chunk: usize) -> usize {
    let mut count = 0;
    stream
        .read(chunk, |part| {
            count += part.len();
            Ok::<(), IoError>(())
        })
        .unwrap();
    count
}

#[test]
fn text_is_read_whole_within_the_budget_and_refused_beyond_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.xyz");
    let text: String = (0..100).map(|i| format!("{i} {} 0.5\n", i % 9)).collect();
    std::fs::write(&path, &text).unwrap();
    let mut stream = PointStream::open(&path, None, PLENTY).unwrap();
    assert!(!stream.is_chunked());
    assert_eq!(points_read(&mut stream, 30), 100);
    let small = MemoryBudget { bytes: text.len() as u64 };
    let error = PointStream::open(&path, None, small).err().expect("over the budget").to_string();
    assert!(error.contains("cloud.xyz") && error.contains("cannot be read in chunks"), "{error}");
}

/// A raw sweep of `count` records of `width` float32: positions, an 8-bit intensity and,
/// for width 5, a ring.
fn write_sweep(path: &Path, count: usize, width: usize) -> Vec<f32> {
    let values: Vec<f32> = (0..count)
        .flat_map(|i| {
            let record =
                [i as f32 * 0.25, (i % 11) as f32, 2.0 + (i % 5) as f32, (i % 256) as f32, (i % 32) as f32];
            record.into_iter().take(width)
        })
        .collect();
    std::fs::write(path, le_bytes(&values)).unwrap();
    values
}

#[test]
fn raw_sweeps_in_chunks_read_as_a_whole() {
    let dir = tempfile::tempdir().unwrap();
    for (name, width) in [("sweep.bin", 4), ("sweep.pcd.bin", 5)] {
        let path = dir.path().join(name);
        write_sweep(&path, 1000, width);
        let whole = read_point_cloud(&path).unwrap();
        let stream = PointStream::open(&path, None, PLENTY).unwrap();
        assert_eq!(stream.sensor_position(), Some(DVec3::ZERO), "{name}: records are in the sensor's frame");
        let chunks = chunked(&path, 64);
        assert_eq!(chunks.positions, whole.positions, "{name}");
        assert_eq!(chunks.intensities, whole.intensities, "{name}: scaled by the whole file's range");
        assert_eq!(chunks.rings, whole.rings, "{name}");
        assert_eq!(whole.rings.is_some(), width == 5);
    }
}

#[test]
fn a_raw_sweep_that_misreads_is_refused_as_a_whole_read_refuses_it() {
    let dir = tempfile::tempdir().unwrap();
    let whole_error = |path: &Path| read_point_cloud(path).unwrap_err().to_string();
    // Five floats a point under a KITTI name: not whole records of four.
    let uneven = dir.path().join("uneven.bin");
    write_sweep(&uneven, 999, 5);
    let error = PointStream::open(&uneven, None, PLENTY).err().expect("refused").to_string();
    assert_eq!(error, whole_error(&uneven));
    assert!(error.contains("uneven.bin") && error.contains("not a multiple of 16"), "{error}");
    // A negative intensity far into the file, past the first chunks.
    let late = dir.path().join("late.bin");
    let mut values = write_sweep(&late, 1000, 4);
    values[900 * 4 + 3] = -1.0;
    std::fs::write(&late, le_bytes(&values)).unwrap();
    let mut stream = PointStream::open(&late, None, PLENTY).unwrap();
    let error = stream.survey(64, |_| Ok::<(), IoError>(())).unwrap_err().to_string();
    assert_eq!(error, whole_error(&late));
    assert!(error.contains("point 900 has a negative or non-finite intensity"), "{error}");
}

fn le_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|value| value.to_le_bytes()).collect()
}

#[test]
fn a_failing_taker_stops_the_read_and_its_error_is_the_one_returned() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cloud.ply");
    let cloud = PointCloud::from_positions((0..1000).map(|i| DVec3::new(i as f64, 0.5, 2.0)).collect());
    write_point_cloud_as(&path, &cloud, PlyEncoding::BinaryLittleEndian).unwrap();
    let mut stream = PointStream::open(&path, None, PLENTY).unwrap();
    let mut taken = 0;
    let error = stream
        .read(100, |part| {
            taken += part.len();
            if taken >= 300 { Err(IoError::unusable("taker", "enough")) } else { Ok(()) }
        })
        .expect_err("the taker fails");
    assert!(error.to_string().contains("enough"), "{error}");
    assert_eq!(taken, 300, "no chunk is taken after the failure");
    assert_eq!(points_read(&mut stream, 100), 1000, "the stream reads whole again after a failed read");
}
