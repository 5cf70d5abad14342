//! The patch store: the versioned binary file that caches a `PatchSet`.
//!
//! All numbers are little-endian. Version 7 layout:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 8 | magic `b"PRPATCH\0"` |
//! | 8 | 4 | format version, u32 = 7 (version 6 stores read too) |
//! | 12 | 4 | header size in bytes, u32 = 208 |
//! | 16 | 8 | point (patch) count `n`, u64 |
//! | 24 | 24 | offset, f64 x 3 (`input = local + offset`) |
//! | 48 | 24 | bounds of all boxes: min xyz, max xyz, f32 x 6 (local coordinates) |
//! | 72 | 64 | section table: (byte offset u64, byte length u64) for aabbs, hot, cold, neighbours |
//! | 136 | 4 | colour neighbours per patch `m`, u32: 0 (no colours) or `COLOR_NEIGHBORS` = 12 |
//! | 140 | 68 | the `PrepSettings` the patches were made with (below) |
//! | 208 | 24 n | aabbs: `Aabb` (min xyz, max xyz, f32) |
//! | section table | 32 n | hot: `PatchHot` (origin with c0 folded in, d_u: f32 x 4; octahedral normal and tangent angle, d_v/d_u and c1, c2..c5 as scaled halves: u32 x 4) |
//! | section table | 12 n | cold: `PatchCold` (RGBA8 u32, intensity f32, colour reach f32) |
//! | section table | 4 m n | neighbours: `m` patch indices per patch (u32, `NO_NEIGHBOR` = unused) |
//! | end - 4 | 4 | CRC-32 (IEEE) of every byte before it, u32 |
//!
//! The settings: `k`, `normal_k` (u32), recompute normals (u32, 0 or 1), radius (u32: 0 paper,
//! 1 adaptive, 2 cell), disk scale (f32), boxes (u32: 0 cube, 1 tight), scan (u32: 0 auto,
//! 1 off), duplicate tolerance (f32, in f32 ulps at each point's coordinates), outlier filter `K`
//! (u32, 0 = none) and `N` (f32), sensor given (u32, 0 or 1), then at 184 the sensor, f64 x 3
//! (zero when not given).
//!
//! Each section lies where the section table puts it: 16-aligned, in this order, at or after
//! the end of the one before; the bytes between sections are zero. `write` leaves no room
//! between them; prep in bounded memory leaves room for one patch per input point
//! (`Layout::with_room`), since it writes each tile's records before the count is known. The
//! file ends 4 bytes after the last section. The record layouts are
//! those of `pointray_kernels::layout`, so the sections can be uploaded to the GPU as
//! they are. `docs/PATCH_STORE.md` describes the same format.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use memmap2::Mmap;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS, PatchCold, PatchHot};

use crate::parallel_checksum;
use crate::patch_records::PatchRecords;
use crate::patch_set::PatchSet;
use crate::prep_settings::{BoxKind, OutlierFilter, PrepSettings, RadiusMode, ScanMode};

pub use crate::patch_store_write::{StoreSummary, write, write_sections, write_to};

pub const MAGIC: [u8; 8] = *b"PRPATCH\0";
pub const FORMAT_VERSION: u32 = 7;
/// Version 6 stores are version 7's with no room between sections.
const READABLE_VERSIONS: std::ops::RangeInclusive<u32> = 6..=FORMAT_VERSION;
pub(crate) const SECTION_COUNT: usize = 4;
pub(crate) const HEADER_BYTES: usize = std::mem::size_of::<Header>();
const CHECKSUM_BYTES: usize = 4;
pub(crate) const SECTION_ALIGNMENT: usize = 16;

#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a pointray patch store (wrong magic)")]
    NotAPatchStore { path: PathBuf },
    #[error(
        "{path}: patch store version {found}, this build reads versions 6 and {FORMAT_VERSION}: re-run `pointray prep`"
    )]
    WrongVersion { path: PathBuf, found: u32 },
    #[error("{path}: truncated or wrong length: the header implies {expected} bytes, the file has {actual}")]
    WrongLength { path: PathBuf, expected: u64, actual: u64 },
    #[error("{path}: corrupted: checksum mismatch")]
    ChecksumMismatch { path: PathBuf },
    #[error("{path}: malformed patch store: {problem}")]
    Malformed { path: PathBuf, problem: String },
    #[error("{path}: cannot store an inconsistent patch set: {problem}")]
    InconsistentPatchSet { path: PathBuf, problem: String },
}

#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Section {
    pub offset: u64,
    pub length: u64,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct Header {
    pub magic: [u8; 8],
    pub version: u32,
    pub header_bytes: u32,
    pub point_count: u64,
    pub offset: [f64; 3],
    pub bounds_min: [f32; 3],
    pub bounds_max: [f32; 3],
    pub sections: [Section; SECTION_COUNT],
    pub neighbor_slots: u32,
    pub settings: StoredSettings,
    pub sensor: [f64; 3],
}

/// `PrepSettings` as the header holds it, but for the sensor, which follows at an 8-byte
/// boundary.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub(crate) struct StoredSettings {
    k: u32,
    normal_k: u32,
    recompute_normals: u32,
    radius: u32,
    disk_scale: f32,
    boxes: u32,
    scan: u32,
    duplicate_tolerance: f32,
    outlier_neighbors: u32,
    outlier_sigmas: f32,
    sensor_given: u32,
}

/// Where each section lies: in order, each at a 16-aligned offset, each holding `n` records.
pub struct Layout {
    pub sections: [Section; SECTION_COUNT],
    pub total_bytes: u64,
}

impl Layout {
    /// The sections of `n` patches with `neighbor_slots` colour neighbours each, back to back.
    pub fn new(n: u64, neighbor_slots: u32) -> Option<Self> {
        Self::with_room(n, n, neighbor_slots)
    }

    /// The sections of `n` patches, each placed with room for `room` patches, so that a
    /// writer that knows only a bound on the count can write every section as it comes.
    pub(crate) fn with_room(n: u64, room: u64, neighbor_slots: u32) -> Option<Self> {
        let mut cursor = HEADER_BYTES as u64;
        let mut sections = [Section::zeroed(); SECTION_COUNT];
        for (section, stride) in sections.iter_mut().zip(strides(neighbor_slots)) {
            let offset = cursor.checked_next_multiple_of(SECTION_ALIGNMENT as u64)?;
            *section = Section { offset, length: n.checked_mul(stride)? };
            cursor = offset.checked_add(room.max(n).checked_mul(stride)?)?;
        }
        Self::of_table(sections, n, neighbor_slots)
    }

    /// The layout of a header's section table, if its sections lie in order after the
    /// header, at aligned offsets, each holding `n` records.
    fn of_table(sections: [Section; SECTION_COUNT], n: u64, neighbor_slots: u32) -> Option<Self> {
        let mut cursor = HEADER_BYTES as u64;
        for (section, stride) in sections.iter().zip(strides(neighbor_slots)) {
            let placed = section.offset >= cursor && section.offset % SECTION_ALIGNMENT as u64 == 0;
            if !placed || section.length != n.checked_mul(stride)? {
                return None;
            }
            cursor = section.offset.checked_add(section.length)?;
        }
        Some(Self { sections, total_bytes: cursor.checked_add(CHECKSUM_BYTES as u64)? })
    }
}

/// The bytes of one patch's record in each section.
fn strides(neighbor_slots: u32) -> [u64; SECTION_COUNT] {
    let neighbors = size_of::<u32>() * neighbor_slots as usize;
    [size_of::<Aabb>(), size_of::<PatchHot>(), size_of::<PatchCold>(), neighbors].map(|bytes| bytes as u64)
}

impl StoredSettings {
    pub(crate) fn of(settings: &PrepSettings) -> Self {
        let filter = settings.remove_outliers;
        Self {
            k: settings.k,
            normal_k: settings.normal_k,
            recompute_normals: settings.recompute_normals.into(),
            radius: settings.radius.code(),
            disk_scale: settings.disk_scale,
            boxes: settings.boxes.code(),
            scan: settings.scan.code(),
            duplicate_tolerance: settings.duplicate_tolerance,
            outlier_neighbors: filter.map_or(0, |f| f.neighbors),
            outlier_sigmas: filter.map_or(0.0, |f| f.sigmas),
            sensor_given: settings.sensor.is_some().into(),
        }
    }

    /// The settings, or which code no store of this format holds.
    fn decode(&self, sensor: [f64; 3]) -> Result<PrepSettings, &'static str> {
        let flag = |value: u32, what| match value {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(what),
        };
        Ok(PrepSettings {
            k: self.k,
            normal_k: self.normal_k,
            recompute_normals: flag(self.recompute_normals, "unknown recompute-normals flag")?,
            sensor: flag(self.sensor_given, "unknown sensor flag")?.then(|| DVec3::from_array(sensor)),
            remove_outliers: (self.outlier_neighbors != 0)
                .then_some(OutlierFilter { neighbors: self.outlier_neighbors, sigmas: self.outlier_sigmas }),
            radius: RadiusMode::from_code(self.radius).ok_or("unknown radius mode")?,
            disk_scale: self.disk_scale,
            boxes: BoxKind::from_code(self.boxes).ok_or("unknown box kind")?,
            scan: ScanMode::from_code(self.scan).ok_or("unknown scan mode")?,
            duplicate_tolerance: self.duplicate_tolerance,
        })
    }
}

/// Reads a patch store, checking, in order, the magic, the version, the length and the
/// checksum. The file is mapped, not read: its sections are the page cache's pages, which the
/// checksum reads on every core and the renderers read again as they upload or trace, so a
/// store larger than the machine's free memory still loads. Where the file system cannot map
/// it, it is read into memory instead.
pub fn read(path: &Path) -> Result<PatchSet, StoreError> {
    let started = Instant::now();
    let io = |source| StoreError::Io { path: path.to_path_buf(), source };
    let file = std::fs::File::open(path).map_err(io)?;
    // SAFETY: the map is only read. `prep` and the cache replace a store by renaming a new
    // file over it, which leaves a mapped one whole; only another program writing into the
    // store in place could change it under the checks below, or end this one by cutting it
    // short (SIGBUS), as it would any reader that maps.
    let map = match unsafe { Mmap::map(&file) } {
        Ok(map) => Arc::new(map),
        Err(error) => {
            tracing::warn!("{}: cannot be mapped ({error}); reading it into memory", path.display());
            return read_from(&std::fs::read(path).map_err(io)?, path);
        }
    };
    let patches = checked_store(path, &map, |[aabbs, hot, cold, neighbors]| {
        Ok(Records {
            aabbs: mapped_section(&map, aabbs, path)?,
            hot: mapped_section(&map, hot, path)?,
            cold: mapped_section(&map, cold, path)?,
            color_neighbors: mapped_section(&map, neighbors, path)?,
        })
    })?;
    let (gigabytes, seconds) = (map.len() as f64 / 1e9, started.elapsed().as_secs_f64());
    tracing::info!(
        "read {}: {} patches, {gigabytes:.2} GB in {seconds:.2} s ({:.2} GB/s)",
        path.display(),
        patches.len(),
        gigabytes / seconds.max(1e-9)
    );
    Ok(patches)
}

/// The records of `section` of a mapped store, which `checked_header` has placed inside it
/// at an aligned offset.
fn mapped_section<T: Pod>(
    map: &Arc<Mmap>,
    section: Section,
    path: &Path,
) -> Result<PatchRecords<T>, StoreError> {
    let range = section.offset as usize..(section.offset + section.length) as usize;
    PatchRecords::mapped(map.clone(), range).ok_or_else(|| StoreError::Malformed {
        path: path.to_path_buf(),
        problem: "a section does not hold whole, aligned records".into(),
    })
}

/// Reads a patch store held in memory; `path` names it in errors.
pub fn read_from(bytes: &[u8], path: &Path) -> Result<PatchSet, StoreError> {
    let section = |Section { offset, length }: Section| &bytes[offset as usize..(offset + length) as usize];
    checked_store(path, bytes, |[aabbs, hot, cold, neighbors]| {
        Ok(Records {
            aabbs: bytemuck::pod_collect_to_vec(section(aabbs)).into(),
            hot: bytemuck::pod_collect_to_vec(section(hot)).into(),
            cold: bytemuck::pod_collect_to_vec(section(cold)).into(),
            color_neighbors: bytemuck::pod_collect_to_vec(section(neighbors)).into(),
        })
    })
}

/// The patch set of a whole store's `bytes`, its `records` taken from the sections the header
/// places, once every check has passed: the same checks whether the bytes are mapped or read.
fn checked_store(
    path: &Path,
    bytes: &[u8],
    records: impl FnOnce([Section; SECTION_COUNT]) -> Result<Records, StoreError>,
) -> Result<PatchSet, StoreError> {
    let (header, layout) = checked_header(path, bytes)?;
    let (body, stored) = bytes.split_at(bytes.len() - CHECKSUM_BYTES);
    let records = records(layout.sections)?;
    checked_patches(path, &header, (parallel_checksum::checksum(body), stored), records)
}

/// A store's four sections, read or mapped but not yet checked.
struct Records {
    aabbs: PatchRecords<Aabb>,
    hot: PatchRecords<PatchHot>,
    cold: PatchRecords<PatchCold>,
    color_neighbors: PatchRecords<u32>,
}

/// The header and the layout its section table gives, once magic, version, colour
/// neighbours, the section table and the length of the file's `bytes` have been verified.
fn checked_header(path: &Path, bytes: &[u8]) -> Result<(Header, Layout), StoreError> {
    let length = bytes.len() as u64;
    let path_buf = || path.to_path_buf();
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(StoreError::NotAPatchStore { path: path_buf() });
    }
    let too_short = || StoreError::WrongLength {
        path: path_buf(),
        expected: (HEADER_BYTES + CHECKSUM_BYTES) as u64,
        actual: length,
    };
    let version_bytes = bytes.get(8..12).ok_or_else(too_short)?;
    let found = u32::from_le_bytes(version_bytes.try_into().expect("four bytes"));
    if !READABLE_VERSIONS.contains(&found) {
        return Err(StoreError::WrongVersion { path: path_buf(), found });
    }
    let header: Header = bytemuck::pod_read_unaligned(bytes.get(..HEADER_BYTES).ok_or_else(too_short)?);
    if header.neighbor_slots != 0 && header.neighbor_slots as usize != COLOR_NEIGHBORS {
        return Err(StoreError::Malformed {
            path: path_buf(),
            problem: format!(
                "{} colour neighbours per patch; 0 or {COLOR_NEIGHBORS} allowed",
                header.neighbor_slots
            ),
        });
    }
    let layout =
        Layout::of_table(header.sections, header.point_count, header.neighbor_slots).ok_or_else(|| {
            StoreError::Malformed {
                path: path_buf(),
                problem: "the section table does not hold the point count's records in order".into(),
            }
        })?;
    let back_to_back = Layout::new(header.point_count, header.neighbor_slots).map(|exact| exact.sections);
    if found < FORMAT_VERSION && back_to_back != Some(layout.sections) {
        return Err(StoreError::Malformed {
            path: path_buf(),
            problem: format!("a version {found} store leaves no room between its sections"),
        });
    }
    if layout.total_bytes != length {
        return Err(StoreError::WrongLength {
            path: path_buf(),
            expected: layout.total_bytes,
            actual: length,
        });
    }
    Ok((header, layout))
}

/// The patch set of `records` with the header's settings and offset, once the checksum
/// (`computed` against `stored`), the header's size, the settings' codes and every record
/// have been verified.
fn checked_patches(
    path: &Path,
    header: &Header,
    (computed, stored): (u32, &[u8]),
    records: Records,
) -> Result<PatchSet, StoreError> {
    if stored != computed.to_le_bytes() {
        return Err(StoreError::ChecksumMismatch { path: path.to_path_buf() });
    }
    let malformed =
        |problem: &str| StoreError::Malformed { path: path.to_path_buf(), problem: problem.into() };
    if header.header_bytes as usize != HEADER_BYTES {
        return Err(malformed("the header size is not this version's"));
    }
    let settings = header.settings.decode(header.sensor).map_err(malformed)?;
    let Records { aabbs, hot, cold, color_neighbors } = records;
    let offset = DVec3::from_array(header.offset);
    let patches = PatchSet { settings, offset, aabbs, hot, cold, color_neighbors };
    // A store can pass its checksum and still hold numbers no renderer can build on.
    patches.check().map_err(|problem| malformed(&problem))?;
    Ok(patches)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_208_bytes_and_sections_are_aligned() {
        assert_eq!(HEADER_BYTES, 208);
        assert_eq!(std::mem::offset_of!(Header, settings), 140);
        assert_eq!(std::mem::offset_of!(Header, sensor), 184);
        let layout = Layout::new(3, COLOR_NEIGHBORS as u32).unwrap();
        assert!(layout.sections.iter().all(|s| s.offset % 16 == 0));
        assert_eq!(layout.sections[0], Section { offset: 208, length: 72 });
        assert_eq!(layout.sections[1], Section { offset: 288, length: 96 });
        assert_eq!(layout.sections[2], Section { offset: 384, length: 36 });
        assert_eq!(layout.sections[3], Section { offset: 432, length: 144 });
        assert_eq!(layout.total_bytes, 580);
        let without = Layout::new(3, 0).unwrap();
        assert_eq!(without.sections[3], Section { offset: 432, length: 0 });
        assert_eq!(without.total_bytes, 436);
        assert!(Layout::new(u64::MAX, 0).is_none());
    }

    #[test]
    fn room_moves_the_sections_but_not_their_lengths() {
        let layout = Layout::with_room(3, 5, COLOR_NEIGHBORS as u32).unwrap();
        assert_eq!(layout.sections[0], Section { offset: 208, length: 72 });
        assert_eq!(layout.sections[1], Section { offset: 336, length: 96 });
        assert_eq!(layout.sections[2], Section { offset: 496, length: 36 });
        assert_eq!(layout.sections[3], Section { offset: 560, length: 144 });
        assert_eq!(layout.total_bytes, 708, "the last section's room is not kept");
        assert_eq!(Layout::of_table(layout.sections, 3, COLOR_NEIGHBORS as u32).unwrap().total_bytes, 708);
        assert!(Layout::of_table(layout.sections, 4, COLOR_NEIGHBORS as u32).is_none());
        assert!(Layout::with_room(3, u64::MAX, 0).is_none());
    }
}
