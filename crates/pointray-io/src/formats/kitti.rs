//! KITTI-style raw Velodyne scans (`.bin`): little-endian f32 quadruples
//! (x, y, z, reflectance), no header.

use std::path::Path;

use glam::DVec3;

use super::intensity::normalise_intensities;
use crate::{IoError, PointCloud};

const RECORD_BYTES: usize = 16;

/// Reads a KITTI `.bin` scan. The frame is the sensor's own, so the sensor position is the
/// origin. Reflectance is normalised to [0, 1] (KITTI already stores it so; other
/// exporters of this layout use 0-255).
pub fn read_kitti_bin(path: &Path) -> Result<PointCloud, IoError> {
    let bytes = std::fs::read(path).map_err(|source| IoError::os(path, source))?;
    read_kitti_bin_from(&bytes, path)
}

/// Reads KITTI `.bin` data held in memory; `origin` names it in errors.
pub fn read_kitti_bin_from(bytes: &[u8], origin: &Path) -> Result<PointCloud, IoError> {
    if !bytes.len().is_multiple_of(RECORD_BYTES) {
        let problem = format!(
            "KITTI .bin length {} is not a multiple of {RECORD_BYTES} (f32 x, y, z, intensity per point)",
            bytes.len()
        );
        return Err(IoError::malformed(origin, problem));
    }
    let records: Vec<[f32; 4]> = bytes.chunks_exact(RECORD_BYTES).map(decode_record).collect();
    if let Some(index) = records.iter().position(|record| !record[..3].iter().all(|c| c.is_finite())) {
        return Err(IoError::malformed(origin, format!("point {index} has a non-finite coordinate")));
    }
    let raw_intensities: Vec<f64> = records.iter().map(|record| f64::from(record[3])).collect();
    let positions = records.iter().map(|r| DVec3::new(r[0].into(), r[1].into(), r[2].into())).collect();
    Ok(PointCloud {
        intensities: normalise_intensities(&raw_intensities),
        sensor_position: Some(DVec3::ZERO),
        ..PointCloud::from_positions(positions)
    })
}

fn decode_record(record: &[u8]) -> [f32; 4] {
    std::array::from_fn(|i| {
        let at = i * 4;
        f32::from_le_bytes([record[at], record[at + 1], record[at + 2], record[at + 3]])
    })
}
