//! An Ouster sensor's metadata JSON (`sensor_metadata.json`): its beam altitude table and where
//! its beams leave the head. With it, each return's beam follows from its elevation exactly.
//!
//! Ouster beams leave from a ring of radius `lidar_origin_to_beam_origin_mm` around the lidar
//! origin, which sits `lidar_to_sensor_transform`'s translation away from the sensor frame's
//! origin (the base of the housing). Seen from that ring, every return of a beam lies at the
//! beam's altitude; seen from the origin, near returns would drift by degrees.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::Value;

use crate::IoError;

/// The name Ouster's tools give the metadata file.
pub const METADATA_FILE_NAME: &str = "sensor_metadata.json";

/// The metadata fits a sweep when at least this share of returns lie on its beams.
const MIN_FITTING_SHARE: f64 = 0.95;

/// A return lies on a beam when its elevation is within this share of the beam spacing.
const BEAM_TOLERANCE: f64 = 0.25;

/// What pointray needs of an Ouster sensor's metadata.
#[derive(Clone, Debug, PartialEq)]
pub struct OusterMetadata {
    /// Beam altitudes, radians, in the sensor's beam order (top first).
    pub beam_altitudes: Vec<f64>,
    /// The lidar origin in the sensor frame, metres.
    pub lidar_origin: DVec3,
    /// The radius of the ring the beams leave from, metres.
    pub beam_origin_radius: f64,
    /// The file it was read from.
    pub path: PathBuf,
}

impl OusterMetadata {
    /// The metadata beside `sweep`, if there is any.
    pub fn beside(sweep: &Path) -> Result<Option<Self>, IoError> {
        let path = sweep.with_file_name(METADATA_FILE_NAME);
        if !path.is_file() {
            return Ok(None);
        }
        Self::read(&path).map(Some)
    }

    pub fn read(path: &Path) -> Result<Self, IoError> {
        let text = std::fs::read_to_string(path).map_err(|source| IoError::os(path, source))?;
        let json: Value = serde_json::from_str(&text)
            .map_err(|error| IoError::malformed(path, format!("not JSON: {error}")))?;
        Self::from_json(&json, path).map_err(|problem| IoError::malformed(path, problem))
    }

    /// Reads both the flat layout of older firmware and the nested one (`beam_intrinsics`,
    /// `lidar_intrinsics`) of newer tools.
    fn from_json(json: &Value, path: &Path) -> Result<Self, String> {
        let field = |nest: &str, name: &str| json.get(name).or_else(|| json.get(nest)?.get(name));
        let altitudes = numbers(field("beam_intrinsics", "beam_altitude_angles"), "beam_altitude_angles")?;
        let radius_mm =
            field("beam_intrinsics", "lidar_origin_to_beam_origin_mm").and_then(Value::as_f64).unwrap_or(0.0);
        let transform =
            numbers(field("lidar_intrinsics", "lidar_to_sensor_transform"), "lidar_to_sensor_transform")?;
        if altitudes.len() < 2 || altitudes.iter().any(|a| !(-90.0..=90.0).contains(a)) {
            return Err("beam_altitude_angles must hold two or more angles within ±90°".into());
        }
        if transform.len() != 16 || !radius_mm.is_finite() {
            return Err("lidar_to_sensor_transform must hold 16 numbers".into());
        }
        Ok(Self {
            beam_altitudes: altitudes.iter().map(|a| a.to_radians()).collect(),
            lidar_origin: DVec3::new(transform[3], transform[7], transform[11]) / 1000.0,
            beam_origin_radius: radius_mm / 1000.0,
            path: path.to_path_buf(),
        })
    }

    /// Per return, its beam (the index in the altitude table), or an error naming both files
    /// when the sweep's returns do not lie on the table's beams.
    pub fn beams(&self, positions: &[DVec3], sweep: &Path) -> Result<Vec<u16>, IoError> {
        let fits: Vec<(u16, bool)> = positions.iter().map(|&p| self.nearest_beam(p)).collect();
        let fitting = fits.iter().filter(|(_, fits)| *fits).count();
        if (fitting as f64) < MIN_FITTING_SHARE * positions.len() as f64 {
            let share = 100.0 * fitting as f64 / positions.len().max(1) as f64;
            return Err(IoError::malformed(
                sweep,
                format!(
                    "{} does not fit this sweep: only {share:.1}% of its returns lie on the metadata's beams \
                     (move the metadata away if it belongs to another sensor)",
                    self.path.display()
                ),
            ));
        }
        Ok(fits.into_iter().map(|(beam, _)| beam).collect())
    }

    /// The beam whose altitude is nearest the return's elevation seen from the beam ring, and
    /// whether it lies within `BEAM_TOLERANCE` of that beam's spacing.
    fn nearest_beam(&self, position: DVec3) -> (u16, bool) {
        let offset = position - self.lidar_origin;
        let elevation = offset.z.atan2(offset.x.hypot(offset.y) - self.beam_origin_radius);
        let distance = |beam: usize| (self.beam_altitudes[beam] - elevation).abs();
        let nearest =
            (0..self.beam_altitudes.len()).min_by(|&a, &b| distance(a).total_cmp(&distance(b))).unwrap_or(0);
        let spacing = self.spacing_at(nearest);
        (nearest as u16, distance(nearest) <= BEAM_TOLERANCE * spacing)
    }

    /// The altitude gap between `beam` and its nearest neighbour in the table.
    fn spacing_at(&self, beam: usize) -> f64 {
        let altitude = self.beam_altitudes[beam];
        self.beam_altitudes
            .iter()
            .enumerate()
            .filter(|&(other, _)| other != beam)
            .map(|(_, &other)| (other - altitude).abs())
            .fold(f64::INFINITY, f64::min)
    }
}

fn numbers(value: Option<&Value>, name: &str) -> Result<Vec<f64>, String> {
    let missing = || format!("missing {name}");
    let values = value.ok_or_else(missing)?;
    let values: Vec<&Value> = match values {
        Value::Array(values) => values.iter().collect(),
        single => vec![single],
    };
    values
        .iter()
        .map(|v| v.as_f64().filter(|v| v.is_finite()).ok_or_else(|| format!("{name} must hold numbers")))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn metadata() -> OusterMetadata {
        let json = serde_json::json!({
            "beam_altitude_angles": [2.0, 1.0, 0.0, -1.0],
            "lidar_origin_to_beam_origin_mm": 15.0,
            "lidar_to_sensor_transform": [-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.0, 0, 0, 0, 1]
        });
        OusterMetadata::from_json(&json, Path::new("sensor_metadata.json")).unwrap()
    }

    /// A return of the beam at `altitude` degrees, `range` metres along it from the beam ring.
    fn return_at(meta: &OusterMetadata, altitude: f64, azimuth: f64, range: f64) -> DVec3 {
        let (a, e) = (azimuth.to_radians(), altitude.to_radians());
        let radial = meta.beam_origin_radius + range * e.cos();
        meta.lidar_origin + DVec3::new(radial * a.cos(), radial * a.sin(), range * e.sin())
    }

    #[test]
    fn near_returns_find_their_beam_from_the_ring() {
        let meta = metadata();
        let positions: Vec<DVec3> =
            (0..40).map(|i| return_at(&meta, 2.0 - (i % 4) as f64, i as f64 * 9.0, 0.5 + i as f64)).collect();
        let beams = meta.beams(&positions, Path::new("scan.bin")).unwrap();
        assert!(beams.iter().enumerate().all(|(i, &beam)| usize::from(beam) == i % 4));
    }

    #[test]
    fn metadata_of_another_sensor_is_refused_naming_it() {
        let meta = metadata();
        let positions: Vec<DVec3> = (0..40).map(|i| return_at(&meta, 0.5, i as f64 * 9.0, 10.0)).collect();
        let error = meta.beams(&positions, Path::new("scan.bin")).unwrap_err().to_string();
        assert!(error.contains("sensor_metadata.json") && error.contains("scan.bin"), "{error}");
    }

    #[test]
    fn the_nested_layout_reads_too() {
        let json = serde_json::json!({
            "beam_intrinsics": {"beam_altitude_angles": [1.0, -1.0], "lidar_origin_to_beam_origin_mm": 27.0},
            "lidar_intrinsics": {"lidar_to_sensor_transform": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 36.0, 0, 0, 0, 1]}
        });
        let meta = OusterMetadata::from_json(&json, Path::new("m.json")).unwrap();
        assert_eq!(meta.beam_altitudes.len(), 2);
        assert!((meta.beam_origin_radius - 0.027).abs() < 1e-12);
    }
}
