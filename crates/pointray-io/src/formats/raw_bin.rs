//! Raw LiDAR sweeps (`.bin`): little-endian float32 records with no header, in the sensor's
//! own frame. KITTI (Velodyne) writes 4 floats a point (x, y, z, reflectance); nuScenes
//! (`LIDAR_TOP/*.pcd.bin`) writes 5 (x, y, z, intensity, ring).
//!
//! Nothing in the file says which, and either width can divide the file's length, so a
//! wrong guess reads garbage without failing. The layout therefore comes from the caller's
//! [`ColumnSpec`], else from the name (`.pcd.bin` is nuScenes, any other `.bin` KITTI), and
//! is then checked: the length must be whole records, and every record plausible for the
//! layout (finite coordinates, non-negative finite intensities, rings small whole numbers).
//! A file that fails is refused with what each layout makes of it.

use std::path::Path;

use super::column_rows::ColumnRows;
use super::columns::{Column, ColumnSpec};
use super::laser_origins::block_origins;
use super::ouster_metadata::OusterMetadata;
use super::sweep_order::lines_from_sweep_order;
use crate::{IoError, PointCloud};

const FLOAT_BYTES: usize = 4;

/// Spinning sensors have at most a few hundred beams; a larger "ring" means the records
/// are being read at the wrong width.
const MAX_PLAUSIBLE_RING: f32 = 1023.0;

/// The two layouts a `.bin` sweep comes in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SweepLayout {
    Kitti,
    NuScenes,
}

impl SweepLayout {
    fn columns(self) -> &'static [Column] {
        use Column::*;
        match self {
            Self::Kitti => &[X, Y, Z, Intensity],
            Self::NuScenes => &[X, Y, Z, Intensity, Ring],
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Self::Kitti => "KITTI (4 float32 a point: x y z intensity; named *.bin)",
            Self::NuScenes => "nuScenes (5 float32 a point: x y z intensity ring; named *.pcd.bin)",
        }
    }

    pub(crate) fn spec(self) -> ColumnSpec {
        ColumnSpec::known(self.columns())
    }

    /// Bytes a record takes.
    pub(crate) fn record_bytes(self) -> usize {
        self.columns().len() * FLOAT_BYTES
    }

    /// The layout a file's name implies.
    pub(crate) fn named_by(path: &Path) -> Self {
        let name = path.file_name().map(|name| name.to_string_lossy().to_ascii_lowercase());
        if name.is_some_and(|name| name.ends_with(".pcd.bin")) { Self::NuScenes } else { Self::Kitti }
    }

    pub(crate) fn other(self) -> Self {
        match self {
            Self::Kitti => Self::NuScenes,
            Self::NuScenes => Self::Kitti,
        }
    }
}

/// Reads a raw sweep. The sensor sits at the origin (the records are in its frame).
/// Intensities are normalised to [0, 1] (KITTI stores them so; other writers of these
/// layouts use 0-255). `columns` overrides the layout the name implies; every column is
/// then float32.
pub fn read_raw_bin(path: &Path, columns: Option<&ColumnSpec>) -> Result<PointCloud, IoError> {
    let bytes = std::fs::read(path).map_err(|source| IoError::os(path, source))?;
    read_raw_bin_from(&bytes, path, columns)
}

/// Reads a raw sweep held in memory; `origin` names it in errors and, without `columns`,
/// its name picks the layout.
pub fn read_raw_bin_from(
    bytes: &[u8],
    origin: &Path,
    columns: Option<&ColumnSpec>,
) -> Result<PointCloud, IoError> {
    let spec = match columns {
        Some(spec) => {
            whole_records(bytes.len(), spec.width())
                .map_err(|problem| IoError::malformed(origin, format!("with columns {spec}: {problem}")))?;
            spec.clone()
        }
        None => inferred_layout(bytes, origin)?.spec(),
    };
    let rows = column_rows(bytes, &spec, 0).map_err(|problem| IoError::malformed(origin, problem))?;
    let cloud = rows.into_point_cloud().map_err(|problem| IoError::malformed(origin, problem))?;
    with_scan_lines(PointCloud { sensor_position: Some(glam::DVec3::ZERO), ..cloud }, origin)
}

/// A sweep without a ring column takes its lines from the Ouster metadata beside it, which
/// also places the sensor at the lidar origin, or else from the order of its returns, with
/// each return seen from its laser block's origin.
fn with_scan_lines(cloud: PointCloud, origin: &Path) -> Result<PointCloud, IoError> {
    if cloud.rings.is_some() {
        return Ok(cloud);
    }
    if let Some(metadata) = OusterMetadata::beside(origin)? {
        let rings = metadata.beams(&cloud.positions, origin)?;
        return Ok(PointCloud { rings: Some(rings), sensor_position: Some(metadata.lidar_origin), ..cloud });
    }
    let Some(rings) = lines_from_sweep_order(&cloud.positions) else { return Ok(cloud) };
    let sensor_origins = block_origins(&cloud.positions, &rings);
    Ok(PointCloud { rings: Some(rings), sensor_origins, ..cloud })
}

/// The records of `bytes` (whole records of `spec`, the first numbered `first`) gathered.
pub(crate) fn column_rows(bytes: &[u8], spec: &ColumnSpec, first: u64) -> Result<ColumnRows, String> {
    let mut rows = ColumnRows::new(spec, bytes.len() / (spec.width() * FLOAT_BYTES));
    let mut values = vec![0.0; spec.width()];
    for (index, record) in bytes.chunks_exact(spec.width() * FLOAT_BYTES).enumerate() {
        for (value, float) in values.iter_mut().zip(floats(record)) {
            *value = f64::from(float);
        }
        rows.push(&values).map_err(|problem| format!("point {}: {problem}", first + index as u64))?;
    }
    Ok(rows)
}

/// The layout the name implies, if the data fits it; otherwise an error saying what each
/// layout makes of the data.
fn inferred_layout(bytes: &[u8], origin: &Path) -> Result<SweepLayout, IoError> {
    let named = SweepLayout::named_by(origin);
    let Err(named_problem) = plausible(bytes, named, 0) else { return Ok(named) };
    Err(misread(origin, named, named_problem, plausible(bytes, named.other(), 0)))
}

/// The error for a sweep that does not read as the layout its name implies, saying what
/// the other layout makes of it.
pub(crate) fn misread(
    origin: &Path,
    named: SweepLayout,
    named_problem: String,
    as_other: Result<(), String>,
) -> IoError {
    let other = named.other();
    let suggestion = match as_other {
        Ok(()) => format!("it does read as {}", other.describe()),
        Err(other_problem) => format!("nor as {}: {other_problem}", other.describe()),
    };
    let problem = format!(
        "does not read as {}: {named_problem}; {suggestion}. Name the columns with a column spec \
         (--columns, or `columns` in a scene), e.g. x,y,z,intensity or x,y,z,intensity,ring",
        named.describe()
    );
    IoError::malformed(origin, problem)
}

/// Whether every record of `bytes` makes sense in `layout` (the first record numbered
/// `first`); the first that does not is the error.
pub(crate) fn plausible(bytes: &[u8], layout: SweepLayout, first: u64) -> Result<(), String> {
    let width = layout.columns().len();
    whole_records(bytes.len(), width)?;
    let mut values = [0.0f32; 5];
    for (index, record) in bytes.chunks_exact(width * FLOAT_BYTES).enumerate() {
        let index = first + index as u64;
        values.iter_mut().zip(floats(record)).for_each(|(value, float)| *value = float);
        let problem = if !values[..3].iter().all(|c| c.is_finite()) {
            "a non-finite coordinate"
        } else if !(values[3].is_finite() && values[3] >= 0.0) {
            "a negative or non-finite intensity"
        } else if layout == SweepLayout::NuScenes
            && !(values[4].fract() == 0.0 && (0.0..=MAX_PLAUSIBLE_RING).contains(&values[4]))
        {
            "a ring that is not a whole number from 0 to 1023"
        } else {
            continue;
        };
        return Err(format!("point {index} has {problem} ({:?})", &values[..width]));
    }
    Ok(())
}

pub(crate) fn whole_records(length: usize, width: usize) -> Result<(), String> {
    let record_bytes = width * FLOAT_BYTES;
    if length.is_multiple_of(record_bytes) {
        Ok(())
    } else {
        Err(format!(
            "length {length} is not a multiple of {record_bytes} ({width} float32 a point); \
             {} bytes are left over",
            length % record_bytes
        ))
    }
}

fn floats(record: &[u8]) -> impl Iterator<Item = f32> + '_ {
    record.chunks_exact(FLOAT_BYTES).map(|bytes| f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
}
