//! Read throughput of each reader on generated 1M-point files. A measurement: it checks only
//! that every file reads back whole, and prints a markdown table of points/s. Run it in
//! release (numbers go to bench/READERS.md):
//!
//! ```sh
//! cargo run --release -p pointray-io --example formats_throughput
//! ```

use std::path::Path;
use std::time::Instant;

use e57::{E57Writer, Record, RecordDataType, RecordName, RecordValue};
use las::point::Format;
use las::{Builder, Color, Transform, Vector};
use pcd_rs::{DataKind, DynRecord, Field};
use pointray_io::PointCloud;
use pointray_io::formats::{
    e57::read_e57, las::read_las, pcd::read_pcd, raw_bin::read_raw_bin, xyz::read_xyz,
};
use pointray_test_support::write_pcd_f32;

const POINTS: usize = 1_000_000;
const RUNS: usize = 3;

/// A deterministic wavy terrain patch with colour and intensity.
fn sample(i: usize) -> ([f64; 3], [u8; 3], u16) {
    let (u, v) = ((i % 1000) as f64 * 0.05, (i / 1000) as f64 * 0.05);
    let position = [500_000.0 + u, 4_000_000.0 + v, 100.0 + (u * 0.3).sin() * (v * 0.2).cos()];
    (
        [position[0], position[1], position[2]],
        [(i % 256) as u8, (i / 256 % 256) as u8, 128],
        (i % 4096) as u16,
    )
}

fn write_las(path: &Path, compressed: bool) {
    let mut builder = Builder::from((1, 2));
    builder.point_format = Format::new(3).unwrap();
    builder.point_format.is_compressed = compressed;
    // Millimetre steps around a geo-referenced origin, as survey tiles store them.
    let around = |offset| Transform { scale: 0.001, offset };
    builder.transforms = Vector { x: around(500_000.0), y: around(4_000_000.0), z: around(0.0) };
    let mut writer = las::Writer::from_path(path, builder.into_header().unwrap()).unwrap();
    for i in 0..POINTS {
        let ([x, y, z], [r, g, b], intensity) = sample(i);
        let color = Some(Color::new(u16::from(r) << 8, u16::from(g) << 8, u16::from(b) << 8));
        writer
            .write_point(las::Point { x, y, z, intensity, color, gps_time: Some(0.0), ..Default::default() })
            .unwrap();
    }
    writer.close().unwrap();
}

fn write_pcd(path: &Path, data_kind: DataKind) {
    let records = (0..POINTS).map(|i| {
        // PCD clouds are usually local: keep f32-friendly coordinates.
        let ([x, y, z], [r, g, b], _) = sample(i);
        let rgb = f32::from_bits(u32::from_be_bytes([0, r, g, b]));
        let fields = [x - 500_000.0, y - 4_000_000.0, z].map(|c| Field::F32(vec![c as f32]));
        DynRecord(fields.into_iter().chain([Field::F32(vec![rgb])]).collect())
    });
    write_pcd_f32(path, data_kind, &["x", "y", "z", "rgb"], records);
}

fn write_e57(path: &Path) {
    let double = |name| Record { name, data_type: RecordDataType::Double { min: None, max: None } };
    let integer = |name, max| Record { name, data_type: RecordDataType::Integer { min: 0, max } };
    let prototype = vec![
        double(RecordName::CartesianX),
        double(RecordName::CartesianY),
        double(RecordName::CartesianZ),
        integer(RecordName::Intensity, 4095),
        integer(RecordName::ColorRed, 255),
        integer(RecordName::ColorGreen, 255),
        integer(RecordName::ColorBlue, 255),
    ];
    let mut writer = E57Writer::from_file(path, "bench").unwrap();
    let mut cloud = writer.add_pointcloud("scan", prototype).unwrap();
    for i in 0..POINTS {
        let ([x, y, z], [r, g, b], intensity) = sample(i);
        let mut values: Vec<RecordValue> = [x, y, z].map(RecordValue::Double).to_vec();
        values.extend([i64::from(intensity), r.into(), g.into(), b.into()].map(RecordValue::Integer));
        cloud.add_point(values).unwrap();
    }
    cloud.finalize().unwrap();
    writer.finalize().unwrap();
}

fn write_xyz(path: &Path) {
    let text: String = (0..POINTS)
        .map(|i| {
            let ([x, y, z], [r, g, b], intensity) = sample(i);
            format!("{x:.3} {y:.3} {z:.3} {intensity} {r} {g} {b}\n")
        })
        .collect();
    std::fs::write(path, text).unwrap();
}

/// A raw sweep: KITTI's 4 floats a point, or nuScenes' 5 with a ring of 32 beams.
fn write_sweep(path: &Path, with_ring: bool) {
    let bytes: Vec<u8> = (0..POINTS)
        .flat_map(|i| {
            let ([x, y, z], _, intensity) = sample(i);
            let record =
                [(x - 500_000.0) as f32, (y - 4_000_000.0) as f32, z as f32, f32::from(intensity) / 4095.0];
            let ring = with_ring.then_some((i % 32) as f32);
            record.into_iter().chain(ring).flat_map(f32::to_le_bytes)
        })
        .collect();
    std::fs::write(path, bytes).unwrap();
}

/// Best of `RUNS` reads, as points per second.
fn measure(name: &str, path: &Path, read: impl Fn(&Path) -> PointCloud) {
    let mut best = f64::INFINITY;
    for _ in 0..RUNS {
        let start = Instant::now();
        let cloud = read(path);
        best = best.min(start.elapsed().as_secs_f64());
        assert_eq!(cloud.len(), POINTS, "{name}");
    }
    let megabytes = std::fs::metadata(path).unwrap().len() as f64 / 1e6;
    println!("| {name} | {megabytes:.1} MB | {:.3} s | {:.2} M points/s |", best, POINTS as f64 / best / 1e6);
}

fn main() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str| dir.path().join(name);
    write_las(&file("cloud.las"), false);
    write_las(&file("cloud.laz"), true);
    write_pcd(&file("ascii.pcd"), DataKind::Ascii);
    write_pcd(&file("binary.pcd"), DataKind::Binary);
    write_pcd(&file("compressed.pcd"), DataKind::BinaryCompressed);
    write_e57(&file("cloud.e57"));
    write_xyz(&file("cloud.xyz"));
    write_sweep(&file("cloud.bin"), false);
    write_sweep(&file("cloud.pcd.bin"), true);
    println!("| reader | file | best of {RUNS} | throughput |\n|---|---|---|---|");
    measure("LAS (format 3)", &file("cloud.las"), |p| read_las(p).unwrap());
    measure("LAZ (format 3)", &file("cloud.laz"), |p| read_las(p).unwrap());
    measure("PCD ascii", &file("ascii.pcd"), |p| read_pcd(p).unwrap());
    measure("PCD binary", &file("binary.pcd"), |p| read_pcd(p).unwrap());
    measure("PCD binary_compressed", &file("compressed.pcd"), |p| read_pcd(p).unwrap());
    measure("E57 (doubles, colour, intensity)", &file("cloud.e57"), |p| read_e57(p).unwrap());
    measure("XYZ text (x y z i r g b)", &file("cloud.xyz"), |p| read_xyz(p, None).unwrap());
    measure("KITTI .bin", &file("cloud.bin"), |p| read_raw_bin(p, None).unwrap());
    measure("nuScenes .pcd.bin", &file("cloud.pcd.bin"), |p| read_raw_bin(p, None).unwrap());
}
