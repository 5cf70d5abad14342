//! Scan lines recovered from real sweeps (data/scans/real/, data/SOURCES.md): a KITTI HDL-64E
//! sweep from its point order alone, Ouster OS-1-32 and OS-1-128 sweeps from the metadata
//! beside them and, without it, from their order; a shuffled sweep gets no lines at all.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use pointray_io::PointCloud;
use pointray_io::formats::read_point_cloud;
use pointray_test_support::data_file;

const RECORD_BYTES: usize = 16;

fn read(path: &Path) -> PointCloud {
    read_point_cloud(path).unwrap_or_else(|error| panic!("{}: {error}", path.display()))
}

/// Returns per line, for a cloud that has lines.
fn line_sizes(cloud: &PointCloud) -> HashMap<u16, usize> {
    let rings = cloud.rings.as_ref().expect("the sweep's lines were not recovered");
    assert_eq!(rings.len(), cloud.len());
    let mut sizes = HashMap::new();
    for &ring in rings {
        *sizes.entry(ring).or_default() += 1;
    }
    sizes
}

/// `sweep` copied alone into a fresh folder, so that no metadata lies beside it.
fn alone(sweep: &Path) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(sweep.file_name().unwrap());
    std::fs::copy(sweep, &path).unwrap();
    (dir, path)
}

#[test]
fn the_kitti_sweep_gives_its_64_beams_from_its_order() {
    let cloud = read(&data_file("scans/real/kitti_hdl64/000000.bin"));
    assert_eq!(cloud.len(), 115_384);
    let sizes = line_sizes(&cloud);
    // The bar is at least 60 of the 64 beams; the order gives every one.
    assert_eq!(sizes.len(), 64, "{} lines", sizes.len());
    let on_full_lines: usize = sizes.values().filter(|&&size| size >= 500).sum();
    let share = on_full_lines as f64 / cloud.len() as f64;
    println!("{} lines; {:.2}% of returns on lines of 500 or more", sizes.len(), 100.0 * share);
    assert!(share >= 0.95, "only {:.1}% of returns lie on lines of 500 returns or more", 100.0 * share);
    // Each of the HDL-64E's laser blocks fires from its own origin.
    assert!(cloud.sensor_origins.is_some(), "no laser-block origins");
}

#[test]
fn the_os1_32_sweep_gives_its_32_beams_with_and_without_its_metadata() {
    let sweep = data_file("scans/real/ouster_os1_32/scan00.bin");
    data_file("scans/real/ouster_os1_32/sensor_metadata.json");
    let with_metadata = read(&sweep);
    assert_eq!(with_metadata.len(), 27_310);
    assert_eq!(line_sizes(&with_metadata).len(), 32);
    let (_dir, bare) = alone(&sweep);
    let from_order = read(&bare);
    assert_eq!(line_sizes(&from_order).len(), 32);
}

#[test]
fn the_os1_128_sweep_gives_its_128_beams_and_its_lidar_origin() {
    let sweep = data_file("scans/real/ouster_os1_128_seq/scan00.bin");
    data_file("scans/real/ouster_os1_128_seq/sensor_metadata.json");
    let with_metadata = read(&sweep);
    assert_eq!(with_metadata.len(), 107_647);
    assert_eq!(line_sizes(&with_metadata).len(), 128);
    // The metadata places the sensor at the lidar origin, 36.18 mm above the housing's base.
    let sensor = with_metadata.sensor_position.expect("a sensor position");
    assert!(sensor.x.abs() < 1e-6 && sensor.y.abs() < 1e-6, "{sensor}");
    assert!((sensor.z - 0.03618).abs() < 1e-4, "{sensor}");
    let (_dir, bare) = alone(&sweep);
    let from_order = read(&bare);
    assert_eq!(line_sizes(&from_order).len(), 128);
}

/// A permutation of `0..count` from a fixed linear congruential sequence (Fisher-Yates).
fn scrambled(count: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..count).collect();
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    for i in (1..count).rev() {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        order.swap(i, ((state >> 33) % (i as u64 + 1)) as usize);
    }
    order
}

#[test]
fn a_shuffled_sweep_gets_no_lines_from_its_order() {
    for sweep in ["scans/real/kitti_hdl64/000000.bin", "scans/real/ouster_os1_32/scan00.bin"] {
        let bytes = std::fs::read(data_file(sweep)).unwrap();
        let records: Vec<&[u8]> = bytes.chunks_exact(RECORD_BYTES).collect();
        let shuffled: Vec<u8> =
            scrambled(records.len()).into_iter().flat_map(|i| records[i]).copied().collect();
        // Alone in its folder: no metadata beside it to take the lines from.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("shuffled.bin");
        std::fs::write(&path, shuffled).unwrap();
        let cloud = read(&path);
        assert_eq!(cloud.len(), records.len());
        assert_eq!(cloud.rings, None, "{sweep}: lines invented for a shuffled copy");
        assert_eq!(cloud.sensor_origins, None, "{sweep}: laser origins invented for a shuffled copy");
    }
}
