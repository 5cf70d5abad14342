//! E57 (ASTM E2807) terrestrial-scan files, read with the `e57` crate.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use e57::{CartesianCoordinate, E57Reader, RecordName};
use glam::DVec3;

use crate::{IoError, PointCloud};

const SUPPORTED: &str = "E57 1.0 point clouds with Cartesian or spherical coordinates";

/// Bytes of the fixed E57 file header: signature, version, lengths and page size.
const HEADER_BYTES: usize = 48;

/// Reads an `.e57` file. Every scan is moved into the file's frame by its pose and the
/// scans are merged into one cloud. The sensor position is the **first** scan's pose
/// translation; a scan without a pose stands at the file's origin, as the E57 standard takes
/// an absent pose for the identity. When several scans are merged, every point also gets its
/// own scan's position (`sensor_origins`).
/// Points without a valid Cartesian position are dropped. Colours, intensities (normalised
/// by the file's own limits) and row indices (the scan lines of a scanner's angular grid,
/// kept as rings when all fit 16 bits) are kept only when every scan has them; a point whose
/// colour is marked invalid is black.
pub fn read_e57(path: &Path) -> Result<PointCloud, IoError> {
    let file = File::open(path).map_err(|source| IoError::os(path, source))?;
    read_e57_from(BufReader::new(file), path)
}

/// Reads E57 data from any seekable stream; `origin` names it in errors.
pub fn read_e57_from<R: Read + Seek>(mut read: R, origin: &Path) -> Result<PointCloud, IoError> {
    let stream_bytes = check_header_lengths(&mut read, origin)?;
    let mut reader = E57Reader::new(read).map_err(|error| e57_error(origin, error))?;
    let scans = reader.pointclouds();
    if scans.is_empty() {
        return Err(IoError::malformed(origin, "E57 file holds no point cloud (data3D is empty)"));
    }
    let mut merged = MergedScans::default();
    for scan in &scans {
        let points = read_scan(&mut reader, scan, stream_bytes).map_err(|error| e57_error(origin, error))?;
        merged.add(scan, points);
    }
    let sensor_position = Some(station_of(&scans[0]));
    Ok(PointCloud { sensor_position, ..merged.into_point_cloud() })
}

/// Where a scan's scanner stood: its pose's translation, or the file's origin without one.
fn station_of(scan: &e57::PointCloud) -> DVec3 {
    scan.transform.as_ref().map_or(DVec3::ZERO, |pose| {
        let t = &pose.translation;
        DVec3::new(t.x, t.y, t.z)
    })
}

/// The E57 crate trusts the header's lengths for its first allocations; a header whose
/// lengths exceed the stream is refused here instead. Returns the stream length.
fn check_header_lengths<R: Read + Seek>(read: &mut R, origin: &Path) -> Result<u64, IoError> {
    let os = |source| IoError::os(origin, source);
    let stream_bytes = read.seek(SeekFrom::End(0)).map_err(os)?;
    read.seek(SeekFrom::Start(0)).map_err(os)?;
    let mut header = [0u8; HEADER_BYTES];
    read.read_exact(&mut header).map_err(|_| {
        IoError::malformed(origin, format!("E57 file is shorter than its {HEADER_BYTES}-byte header"))
    })?;
    read.seek(SeekFrom::Start(0)).map_err(os)?;
    if &header[..8] != b"ASTM-E57" {
        return Err(IoError::malformed(origin, "E57 signature \"ASTM-E57\" missing"));
    }
    let field = |at: usize| u64::from_le_bytes(header[at..at + 8].try_into().unwrap_or_default());
    let (declared_length, xml_offset, xml_length) = (field(16), field(24), field(32));
    if declared_length > stream_bytes || xml_offset.saturating_add(xml_length) > stream_bytes {
        let problem = format!(
            "E57 header declares {declared_length} bytes with XML at {xml_offset}+{xml_length}, \
             but the file has {stream_bytes}"
        );
        return Err(IoError::malformed(origin, problem));
    }
    Ok(stream_bytes)
}

fn e57_error(origin: &Path, error: e57::Error) -> IoError {
    match error {
        e57::Error::NotImplemented { desc } => {
            IoError::Unsupported { path: origin.into(), what: desc, supported: SUPPORTED.into() }
        }
        other => IoError::malformed(origin, format!("not a readable E57 file: {other}")),
    }
}

fn read_scan<R: Read + Seek>(
    reader: &mut E57Reader<R>,
    scan: &e57::PointCloud,
    stream_bytes: u64,
) -> e57::Result<Vec<e57::Point>> {
    let mut points = reader.pointcloud_simple(scan)?;
    // Grey colours made up from intensity would hide that the scan has no colour.
    points.intensity_to_color(false);
    let mut kept = Vec::with_capacity(scan.records.min(stream_bytes) as usize);
    for point in points {
        kept.push(point?);
    }
    Ok(kept)
}

/// Scans merged in file order; an attribute survives only if every scan has it.
#[derive(Default)]
struct MergedScans {
    positions: Vec<DVec3>,
    colors: Option<Vec<[u8; 3]>>,
    intensities: Option<Vec<f32>>,
    rings: Option<Vec<u16>>,
    sensor_origins: Option<Vec<DVec3>>,
    scans: usize,
}

impl MergedScans {
    fn add(&mut self, scan: &e57::PointCloud, points: Vec<e57::Point>) {
        let first = self.scans == 0;
        self.scans += 1;
        let valid: Vec<(DVec3, &e57::Point)> = points
            .iter()
            .filter_map(|point| match point.cartesian {
                CartesianCoordinate::Valid { x, y, z } => Some((DVec3::new(x, y, z), point)),
                _ => None,
            })
            .collect();
        self.positions.extend(valid.iter().map(|(position, _)| *position));
        keep_if_all(&mut self.colors, first, scan.has_color(), || {
            valid.iter().map(|(_, p)| color_8_bit(&p.color))
        });
        keep_if_all(&mut self.intensities, first, scan.has_intensity(), || {
            valid.iter().map(|(_, p)| p.intensity.unwrap_or(0.0).clamp(0.0, 1.0))
        });
        let has_rows = scan.prototype.iter().any(|record| record.name == RecordName::RowIndex)
            && valid.iter().all(|(_, p)| u16::try_from(p.row).is_ok());
        keep_if_all(&mut self.rings, first, has_rows, || valid.iter().map(|(_, p)| p.row as u16));
        let station = station_of(scan);
        keep_if_all(&mut self.sensor_origins, first, true, || std::iter::repeat_n(station, valid.len()));
    }

    fn into_point_cloud(self) -> PointCloud {
        PointCloud {
            colors: self.colors,
            intensities: self.intensities,
            rings: self.rings,
            // One scan's position is the cloud's `sensor_position`.
            sensor_origins: self.sensor_origins.filter(|_| self.scans > 1),
            ..PointCloud::from_positions(self.positions)
        }
    }
}

/// Appends a scan's attribute values when every scan so far had the attribute, and drops
/// the attribute for good as soon as one scan lacks it.
fn keep_if_all<T, I: Iterator<Item = T>>(
    column: &mut Option<Vec<T>>,
    first: bool,
    scan_has_it: bool,
    values: impl FnOnce() -> I,
) {
    if !scan_has_it {
        *column = None;
    } else if first {
        *column = Some(values().collect());
    } else if let Some(column) = column {
        column.extend(values());
    }
}

fn color_8_bit(color: &Option<e57::Color>) -> [u8; 3] {
    let to_byte = |channel: f32| (channel.clamp(0.0, 1.0) * 255.0).round() as u8;
    color.as_ref().map_or([0, 0, 0], |c| [to_byte(c.red), to_byte(c.green), to_byte(c.blue)])
}
