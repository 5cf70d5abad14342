//! The patch store: the versioned binary file that caches a `PatchSet`.
//!
//! All numbers are little-endian. Version 9 layout:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 8 | magic `b"PRPATCH\0"` |
//! | 8 | 4 | format version, u32 = 9 |
//! | 12 | 4 | header size in bytes, u32 = 424 |
//! | 16 | 8 | point (patch) count `n`, u64 |
//! | 24 | 24 | offset, f64 x 3 (`input = local + offset`) |
//! | 48 | 24 | bounds of the origins as stored (of the boxes, for full records): min xyz, max xyz, f32 x 6 (local) |
//! | 72 | 96 | section table: (byte offset u64, byte length u64) for each of the six sections |
//! | 168 | 4 | colour neighbours per patch `m`, u32: 0 (no colours) or `COLOR_NEIGHBORS` = 12 |
//! | 172 | 68 | the `PrepSettings` the patches were made with (below) |
//! | 240 | 4 | record encoding, u32: 0 compact, 1 full |
//! | 244 | 4 | patches a block, u32 = `BLOCK_PATCHES` (compact), 0 (full) |
//! | 248 | 4 | colour columns, u32: 1 when the compact colour section is there, else 0 |
//! | 252 | 4 | scan structure, u32: 0 not recorded, 1 none sought, 2 lines, 3 unstructured |
//! | 256 | 32 | lines, returns on lines, patches, surface patches, u64 x 4 (scan structure 2) |
//! | 288 | 128 | the reason, UTF-8, zero-padded (scan structure 3) |
//! | 416 | 8 | coarse patches `c`, u64 (0 for full records) |
//! | 432 | | the sections, each where the section table puts it |
//! | end - 4 | 4 | CRC-32 (IEEE) of every byte before it, u32 |
//!
//! The sections of the compact encoding (`compact_patches`), which `write` and prep write:
//! block frames (32 bytes a block of `BLOCK_PATCHES` patches), compact patches (28 n),
//! colours and intensities (6 n, or none without colour columns), colour neighbours (4 m n:
//! `m` patch indices per patch, `NO_NEIGHBOR` = unused), then the coarse level
//! (`stored_coarse`): its patches a block (u32 a block) and its records (44 c). The full
//! encoding, which tile files embed so that a merge quantises the records once: an empty
//! section where the block frames would be, `PatchHot` (32 n), `PatchCold` (12 n), colour
//! neighbours (4 m n), the records as the renderers take them, and two empty sections where
//! the coarse level would be. Neither encoding stores the boxes: a reader makes them again
//! from the records (`patch_bounds`), so they bound the patch the renderers see.
//!
//! The settings: `k`, `normal_k` (u32), recompute normals (u32, 0 or 1), radius (u32: 0 paper,
//! 1 adaptive, 2 cell), disk scale (f32), boxes (u32: 0 cube, 1 tight), scan (u32: 0 auto,
//! 1 off), duplicate tolerance (f32, in f32 ulps at each point's coordinates), outlier filter `K`
//! (u32, 0 = none) and `N` (f32), sensor given (u32, 0 or 1), then at 216 the sensor, f64 x 3
//! (zero when not given).
//!
//! Each section lies where the section table puts it: 16-aligned, in this order, at or after
//! the end of the one before; the bytes between sections are zero. `write` leaves no room
//! between them; prep in bounded memory leaves room for one patch per input point after each
//! section before the colour neighbours (`Layout::with_room`), since it writes each tile's
//! records before the count is known; the coarse level follows the colour neighbours, as it
//! is written last. The file ends 4 bytes after the last section. `docs/PATCH_STORE.md` describes the same format.

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use memmap2::Mmap;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS, PatchCold, PatchHot};
use rayon::prelude::*;

use crate::compact_patches::{
    BLOCK_PATCHES, BlockFrame, CompactColor, CompactPatch, cold_problem, colors_of, decode_block,
    frame_problem, frames_of, keeps_colors, patches_of,
};
use crate::parallel_checksum;
use crate::patch_bounds::patch_box;
use crate::patch_checks::check_records;
use crate::patch_records::PatchRecords;
use crate::patch_set::PatchSet;
use crate::prep_settings::{BoxKind, OutlierFilter, PrepSettings, RadiusMode, ScanMode};
use crate::scan_structure::{REASON_BYTES, ScanStructure};
use crate::stored_coarse::{CoarseRecord, level_of_sections};

pub use crate::patch_store_write::{StoreSummary, write, write_to, write_with_scan};

pub const MAGIC: [u8; 8] = *b"PRPATCH\0";
pub const FORMAT_VERSION: u32 = 9;
pub(crate) const SECTION_COUNT: usize = 6;
/// The section of colour neighbours, which name input points until prep in bounded memory
/// finishes its store; the coarse level's sections follow it.
pub(crate) const NEIGHBOR_SECTION: usize = 3;
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
        "{path}: patch store version {found}, this build reads version {FORMAT_VERSION} only: re-run `pointray prep` on the points to make the store again"
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
    pub encoding: u32,
    pub block_patches: u32,
    pub color_columns: u32,
    pub scan_kind: u32,
    pub scan_counts: [u64; 4],
    pub scan_reason: [u8; REASON_BYTES],
    pub coarse_patches: u64,
}

/// How a store holds its records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Quantised within blocks (`compact_patches`): what `write` and prep write.
    Compact,
    /// The hot and cold records as the renderers take them, bit for bit, without the boxes
    /// (made again from them): what tile files embed.
    Full,
}

/// What decides the sections' lengths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordShape {
    pub encoding: Encoding,
    /// Colour neighbours per patch: 0 or `COLOR_NEIGHBORS`.
    pub neighbor_slots: u32,
    /// Whether a compact store has its colour section (always false for the full encoding,
    /// whose cold records hold the colours).
    pub colors: bool,
}

impl RecordShape {
    /// A compact store's shape: colour columns when `colors`.
    pub fn compact(neighbor_slots: u32, colors: bool) -> Self {
        Self { encoding: Encoding::Compact, neighbor_slots, colors }
    }

    pub fn full(neighbor_slots: u32) -> Self {
        Self { encoding: Encoding::Full, neighbor_slots, colors: false }
    }

    /// The bytes of section `index` for `count` patches, of which `coarse` coarse ones.
    fn section_bytes(&self, index: usize, Counts { patches: count, coarse }: Counts) -> Option<u64> {
        let per_patch = |bytes: usize| count.checked_mul(bytes as u64);
        let per_block = |bytes: usize| count.div_ceil(BLOCK_PATCHES as u64).checked_mul(bytes as u64);
        match (self.encoding, index) {
            (_, NEIGHBOR_SECTION) => per_patch(size_of::<u32>() * self.neighbor_slots as usize),
            (Encoding::Full, 1) => per_patch(size_of::<PatchHot>()),
            (Encoding::Full, 2) => per_patch(size_of::<PatchCold>()),
            (Encoding::Full, _) => Some(0),
            (Encoding::Compact, 0) => per_block(size_of::<BlockFrame>()),
            (Encoding::Compact, 1) => per_patch(size_of::<CompactPatch>()),
            (Encoding::Compact, 2) => per_patch(if self.colors { size_of::<CompactColor>() } else { 0 }),
            (Encoding::Compact, 4) => per_block(size_of::<u32>()),
            (Encoding::Compact, _) => coarse.checked_mul(size_of::<CoarseRecord>() as u64),
        }
    }
}

/// The records a store's sections hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Counts {
    pub patches: u64,
    /// The coarse level's patches: 0 for full records.
    pub coarse: u64,
}

impl Counts {
    pub fn new(patches: u64, coarse: u64) -> Self {
        Self { patches, coarse }
    }
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
    /// The sections of `counts`' records of `shape`, back to back.
    pub fn new(counts: Counts, shape: RecordShape) -> Option<Self> {
        Self::with_room(counts, counts.patches, shape)
    }

    /// The sections of `counts`' records, each before the colour neighbours placed with room
    /// for `room` patches, so that a writer that knows only a bound on the count can write
    /// each of those sections as it comes. The colour neighbours are written from their
    /// start as they come, and the coarse level after them last, so it follows their end.
    pub(crate) fn with_room(counts: Counts, room: u64, shape: RecordShape) -> Option<Self> {
        let mut cursor = HEADER_BYTES as u64;
        let mut sections = [Section::zeroed(); SECTION_COUNT];
        let roomy = Counts { patches: room.max(counts.patches), ..counts };
        for (index, section) in sections.iter_mut().enumerate() {
            let offset = cursor.checked_next_multiple_of(SECTION_ALIGNMENT as u64)?;
            *section = Section { offset, length: shape.section_bytes(index, counts)? };
            let room =
                if index < NEIGHBOR_SECTION { shape.section_bytes(index, roomy)? } else { section.length };
            cursor = offset.checked_add(room)?;
        }
        Self::of_table(sections, counts, shape)
    }

    /// The layout of a header's section table, if its sections lie in order after the
    /// header, at aligned offsets, each holding `counts`' records.
    fn of_table(sections: [Section; SECTION_COUNT], counts: Counts, shape: RecordShape) -> Option<Self> {
        let mut cursor = HEADER_BYTES as u64;
        for (index, section) in sections.iter().enumerate() {
            let placed = section.offset >= cursor && section.offset % SECTION_ALIGNMENT as u64 == 0;
            if !placed || section.length != shape.section_bytes(index, counts)? {
                return None;
            }
            cursor = section.offset.checked_add(section.length)?;
        }
        Some(Self { sections, total_bytes: cursor.checked_add(CHECKSUM_BYTES as u64)? })
    }
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

impl Header {
    /// The header's scan structure fields for `scan`, as (kind, counts, reason).
    pub(crate) fn scan_fields(scan: &ScanStructure) -> (u32, [u64; 4], [u8; REASON_BYTES]) {
        let reason = scan.reason_bytes();
        match *scan {
            ScanStructure::NotRecorded => (0, [0; 4], reason),
            ScanStructure::NotSought => (1, [0; 4], reason),
            ScanStructure::Lines { lines, returns_on_lines, patches, surface_patches } => {
                (2, [lines, returns_on_lines, patches, surface_patches], reason)
            }
            ScanStructure::Unstructured { .. } => (3, [0; 4], reason),
        }
    }

    /// The scan structure the header records, or why it records none this build knows.
    fn scan(&self) -> Result<ScanStructure, &'static str> {
        let [lines, returns_on_lines, patches, surface_patches] = self.scan_counts;
        let structure = match self.scan_kind {
            0 => ScanStructure::NotRecorded,
            1 => ScanStructure::NotSought,
            2 => ScanStructure::Lines { lines, returns_on_lines, patches, surface_patches },
            3 => ScanStructure::Unstructured { reason: ScanStructure::reason_of(&self.scan_reason)? },
            _ => return Err("unknown scan structure kind"),
        };
        Ok(structure)
    }

    /// The records the sections hold.
    fn counts(&self) -> Counts {
        Counts::new(self.point_count, self.coarse_patches)
    }

    /// The shape of the records, or which code this build does not know.
    fn shape(&self) -> Result<RecordShape, &'static str> {
        let neighbor_slots = self.neighbor_slots;
        if self.encoding == 1 && self.coarse_patches != 0 {
            return Err("full records with a coarse level");
        }
        match (self.encoding, self.block_patches, self.color_columns) {
            (0, blocks, colors @ (0 | 1)) if blocks as usize == BLOCK_PATCHES => {
                Ok(RecordShape::compact(neighbor_slots, colors == 1))
            }
            (1, 0, 0) => Ok(RecordShape::full(neighbor_slots)),
            (0 | 1, _, _) => Err("the block size or colour columns are not this encoding's"),
            _ => Err("unknown record encoding"),
        }
    }
}

/// What a store's header says, read without its records: `pointray info`.
#[derive(Clone, Debug, PartialEq)]
pub struct StoreDescription {
    pub patches: u64,
    pub file_bytes: u64,
    pub shape: RecordShape,
    pub settings: PrepSettings,
    pub offset: DVec3,
    /// The box of the patches' origins as stored, in local coordinates (`None` for no
    /// patches; the union of the boxes for full records).
    pub bounds: Option<Aabb>,
    pub scan: ScanStructure,
    /// The coarse level's patches (0 for full records).
    pub coarse_patches: u64,
}

/// The header of the store at `path`, checked as `read` checks it but for the checksum and
/// the records, which it does not read.
pub fn describe(path: &Path) -> Result<StoreDescription, StoreError> {
    let io = |source| StoreError::Io { path: path.to_path_buf(), source };
    let mut file = std::fs::File::open(path).map_err(io)?;
    let file_bytes = file.metadata().map_err(io)?.len();
    let mut bytes = Vec::with_capacity(HEADER_BYTES);
    std::io::Read::read_to_end(&mut std::io::Read::take(&mut file, HEADER_BYTES as u64), &mut bytes)
        .map_err(io)?;
    let (header, shape) = checked_header_fields(path, &bytes, file_bytes)?;
    let malformed =
        |problem: &str| StoreError::Malformed { path: path.to_path_buf(), problem: problem.into() };
    let settings = header.settings.decode(header.sensor).map_err(malformed)?;
    let bounds = (header.point_count > 0).then_some(Aabb { min: header.bounds_min, max: header.bounds_max });
    Ok(StoreDescription {
        patches: header.point_count,
        file_bytes,
        shape,
        settings,
        offset: DVec3::from_array(header.offset),
        bounds,
        scan: header.scan().map_err(malformed)?,
        coarse_patches: header.coarse_patches,
    })
}

/// Reads a patch store, checking, in order, the magic, the version, the length and the
/// checksum, then decoding its records. The file is mapped, not read: the checksum reads it
/// on every core, and the colour neighbours (and a full store's records) stay the page
/// cache's pages, which the renderers read as they upload or trace. Where the file system
/// cannot map it, it is read into memory instead.
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
    let patches = checked_store(path, &map, Some(&map))?;
    let (gigabytes, seconds) = (map.len() as f64 / 1e9, started.elapsed().as_secs_f64());
    tracing::info!(
        "read {}: {} patches, {gigabytes:.2} GB in {seconds:.2} s ({:.2} GB/s)",
        path.display(),
        patches.len(),
        gigabytes / seconds.max(1e-9)
    );
    Ok(patches)
}

/// Reads a patch store held in memory; `path` names it in errors.
pub fn read_from(bytes: &[u8], path: &Path) -> Result<PatchSet, StoreError> {
    checked_store(path, bytes, None)
}

/// The patch set of a whole store's `bytes` (which `map`, when given, maps), once every
/// check has passed: the same checks whether the bytes are mapped or read.
fn checked_store(path: &Path, bytes: &[u8], map: Option<&Arc<Mmap>>) -> Result<PatchSet, StoreError> {
    let (shape, layout, settings, offset) = checked_frame(path, bytes)?;
    let malformed =
        |problem: &str| StoreError::Malformed { path: path.to_path_buf(), problem: problem.into() };
    let [first, second, third, neighbors, coarse_counts, coarse_records] = layout.sections;
    let section = |s: Section| &bytes[s.offset as usize..(s.offset + s.length) as usize];
    let (aabbs, hot, cold) = match shape.encoding {
        Encoding::Full => {
            let hot: PatchRecords<PatchHot> = records(section(second), map, second, path)?;
            let aabbs = hot.par_iter().map(|patch| patch_box(patch, settings.boxes)).collect::<Vec<_>>();
            (aabbs.into(), hot, records(section(third), map, third, path)?)
        }
        Encoding::Compact => {
            let colors = shape.colors.then(|| section(third));
            decoded(section(first), section(second), colors, settings.boxes).map_err(malformed)?
        }
    };
    let color_neighbors = records(section(neighbors), map, neighbors, path)?;
    let mut patches = PatchSet { settings, offset, aabbs, hot, cold, color_neighbors, coarse: None };
    // A store can pass its checksum and still hold numbers no renderer can build on.
    patches.check().map_err(|problem| malformed(&problem))?;
    if shape.encoding == Encoding::Compact {
        let counts = cast_or_copy::<u32>(section(coarse_counts));
        let records = cast_or_copy::<CoarseRecord>(section(coarse_records));
        patches.coarse =
            Some(level_of_sections(&counts, &records, &patches).map_err(|problem| malformed(&problem))?);
    }
    Ok(patches)
}

/// A store of the full encoding without colour neighbours, as tile files embed it: its
/// records as they are, without the boxes a `PatchSet` carries, which a merge has no use for.
#[derive(Clone, Debug, PartialEq)]
pub struct FullRecords {
    pub settings: PrepSettings,
    pub offset: DVec3,
    pub hot: Vec<PatchHot>,
    pub cold: Vec<PatchCold>,
}

/// The records of a whole full store held in memory, once every check but the boxes' has
/// passed; `path` names it in errors.
pub fn read_full_records(bytes: &[u8], path: &Path) -> Result<FullRecords, StoreError> {
    let (shape, layout, settings, offset) = checked_frame(path, bytes)?;
    let malformed = |problem: String| StoreError::Malformed { path: path.to_path_buf(), problem };
    if shape != RecordShape::full(0) {
        return Err(malformed("not full records without colour neighbours".into()));
    }
    let [_, hot, cold, ..] =
        layout.sections.map(|s| &bytes[s.offset as usize..(s.offset + s.length) as usize]);
    let (hot, cold) = (bytemuck::pod_collect_to_vec(hot), bytemuck::pod_collect_to_vec(cold));
    check_records(&settings, offset, &hot, &cold).map_err(malformed)?;
    Ok(FullRecords { settings, offset, hot, cold })
}

/// A whole store's shape, layout, settings and offset, once its header and checksum pass.
fn checked_frame(
    path: &Path,
    bytes: &[u8],
) -> Result<(RecordShape, Layout, PrepSettings, DVec3), StoreError> {
    let (header, shape) = checked_header_fields(path, bytes, bytes.len() as u64)?;
    let layout = Layout::of_table(header.sections, header.counts(), shape).expect("checked with the header");
    let (body, stored) = bytes.split_at(bytes.len() - CHECKSUM_BYTES);
    if stored != parallel_checksum::checksum(body).to_le_bytes() {
        return Err(StoreError::ChecksumMismatch { path: path.to_path_buf() });
    }
    let malformed =
        |problem: &str| StoreError::Malformed { path: path.to_path_buf(), problem: problem.into() };
    if header.header_bytes as usize != HEADER_BYTES {
        return Err(malformed("the header size is not this version's"));
    }
    let settings = header.settings.decode(header.sensor).map_err(malformed)?;
    header.scan().map_err(malformed)?;
    Ok((shape, layout, settings, DVec3::from_array(header.offset)))
}

/// The records of `section`: mapped where `map` is given, else copied from `bytes`.
fn records<T: Pod>(
    bytes: &[u8],
    map: Option<&Arc<Mmap>>,
    section: Section,
    path: &Path,
) -> Result<PatchRecords<T>, StoreError> {
    let Some(map) = map else {
        return Ok(bytemuck::pod_collect_to_vec(bytes).into());
    };
    let range = section.offset as usize..(section.offset + section.length) as usize;
    PatchRecords::mapped(map.clone(), range).ok_or_else(|| StoreError::Malformed {
        path: path.to_path_buf(),
        problem: "a section does not hold whole, aligned records".into(),
    })
}

/// The records as `T`, borrowed where the bytes are aligned for them.
fn cast_or_copy<T: Pod>(bytes: &[u8]) -> Cow<'_, [T]> {
    bytemuck::try_cast_slice(bytes)
        .map_or_else(|_| Cow::Owned(bytemuck::pod_collect_to_vec(bytes)), Cow::Borrowed)
}

type DecodedRecords = (PatchRecords<Aabb>, PatchRecords<PatchHot>, PatchRecords<PatchCold>);

/// The boxes (of `kind`), hot and cold records of a compact store's sections, decoded block
/// by block on every core.
fn decoded(
    frames: &[u8],
    patches: &[u8],
    colors: Option<&[u8]>,
    kind: BoxKind,
) -> Result<DecodedRecords, &'static str> {
    let frames = cast_or_copy::<BlockFrame>(frames);
    if let Some(problem) = frames.par_iter().find_map_first(frame_problem) {
        return Err(problem);
    }
    let colors = colors.map(cast_or_copy::<CompactColor>);
    Ok(decoded_records(&frames, &cast_or_copy::<CompactPatch>(patches), colors.as_deref(), kind))
}

fn decoded_records(
    frames: &[BlockFrame],
    patches: &[CompactPatch],
    colors: Option<&[CompactColor]>,
    kind: BoxKind,
) -> DecodedRecords {
    let n = patches.len();
    let (mut hot, mut aabbs, mut cold) =
        (vec![PatchHot::zeroed(); n], vec![Aabb::zeroed(); n], vec![PatchCold::zeroed(); n]);
    hot.par_chunks_mut(BLOCK_PATCHES)
        .zip(aabbs.par_chunks_mut(BLOCK_PATCHES))
        .zip(cold.par_chunks_mut(BLOCK_PATCHES))
        .enumerate()
        .for_each(|(block, ((hot, aabbs), cold))| {
            let range = block * BLOCK_PATCHES..block * BLOCK_PATCHES + hot.len();
            let colors = colors.map(|colors| &colors[range.clone()]);
            decode_block(&frames[block], &patches[range], colors, kind, (hot, aabbs, cold));
        });
    (aabbs.into(), hot.into(), cold.into())
}

/// `patches` as a compact store holds them: what `write` then `read` give, without a file
/// (`path` names them in errors). The scene loader and the Python package hand renderers
/// these, so that a point set renders the same whether it was prepped just now or read from
/// a store, and a second round trip changes nothing.
pub fn as_stored(patches: &PatchSet, path: &Path) -> Result<PatchSet, StoreError> {
    let inconsistent = |problem| StoreError::InconsistentPatchSet { path: path.to_path_buf(), problem };
    patches.check().map_err(inconsistent)?;
    let colors = keeps_colors(patches);
    if let Some(problem) = cold_problem(&patches.cold, colors) {
        return Err(inconsistent(problem));
    }
    let frames = frames_of(&patches.hot, &patches.cold);
    let compact = patches_of(&frames, &patches.hot, &patches.cold);
    let colors = colors.then(|| colors_of(&patches.cold));
    let (aabbs, hot, cold) = decoded_records(&frames, &compact, colors.as_deref(), patches.settings.boxes);
    let (settings, offset, color_neighbors) =
        (patches.settings, patches.offset, patches.color_neighbors.clone());
    Ok(PatchSet { settings, offset, aabbs, hot, cold, color_neighbors, coarse: None })
}

/// The header and the shape of its records, once magic, version, colour neighbours, the
/// codes of the encoding, the section table and the file's length (`length`, of which
/// `bytes` holds at least the header) have been verified.
fn checked_header_fields(
    path: &Path,
    bytes: &[u8],
    length: u64,
) -> Result<(Header, RecordShape), StoreError> {
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
    if found != FORMAT_VERSION {
        return Err(StoreError::WrongVersion { path: path_buf(), found });
    }
    let header: Header = bytemuck::pod_read_unaligned(bytes.get(..HEADER_BYTES).ok_or_else(too_short)?);
    let malformed = |problem: String| StoreError::Malformed { path: path_buf(), problem };
    if header.neighbor_slots != 0 && header.neighbor_slots as usize != COLOR_NEIGHBORS {
        let slots = header.neighbor_slots;
        return Err(malformed(format!(
            "{slots} colour neighbours per patch; 0 or {COLOR_NEIGHBORS} allowed"
        )));
    }
    let shape = header.shape().map_err(|problem| malformed(problem.into()))?;
    let layout = Layout::of_table(header.sections, header.counts(), shape).ok_or_else(|| {
        malformed("the section table does not hold the point count's records in order".into())
    })?;
    if layout.total_bytes != length {
        return Err(StoreError::WrongLength {
            path: path_buf(),
            expected: layout.total_bytes,
            actual: length,
        });
    }
    Ok((header, shape))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_is_424_bytes_and_sections_are_aligned() {
        assert_eq!(HEADER_BYTES, 424);
        assert_eq!(std::mem::offset_of!(Header, settings), 172);
        assert_eq!(std::mem::offset_of!(Header, sensor), 216);
        assert_eq!(std::mem::offset_of!(Header, encoding), 240);
        assert_eq!(std::mem::offset_of!(Header, scan_counts), 256);
        assert_eq!(std::mem::offset_of!(Header, scan_reason), 288);
        assert_eq!(std::mem::offset_of!(Header, coarse_patches), 416);
        let colored = RecordShape::compact(COLOR_NEIGHBORS as u32, true);
        let layout = Layout::new(Counts::new(3, 2), colored).unwrap();
        let sections = layout.sections.map(|s| (s.offset, s.length));
        assert_eq!(sections, [(432, 32), (464, 84), (560, 18), (592, 144), (736, 4), (752, 88)]);
        assert_eq!(layout.total_bytes, 844);
        let plain = Layout::new(Counts::new(3, 0), RecordShape::compact(0, false)).unwrap();
        let sections = plain.sections.map(|s| (s.offset, s.length));
        assert_eq!(sections, [(432, 32), (464, 84), (560, 0), (560, 0), (560, 4), (576, 0)]);
        assert_eq!(plain.total_bytes, 580);
        let full = Layout::new(Counts::new(3, 0), RecordShape::full(COLOR_NEIGHBORS as u32)).unwrap();
        let sections = full.sections.map(|s| (s.offset, s.length));
        assert_eq!(sections, [(432, 0), (432, 96), (528, 36), (576, 144), (720, 0), (720, 0)]);
        assert!(Layout::new(Counts::new(u64::MAX, 0), RecordShape::compact(0, false)).is_none());
    }

    #[test]
    fn room_moves_the_sections_before_the_colour_neighbours_but_not_their_lengths() {
        let shape = RecordShape::compact(COLOR_NEIGHBORS as u32, true);
        let layout = Layout::with_room(Counts::new(3, 1), 5, shape).unwrap();
        let sections = layout.sections.map(|s| (s.offset, s.length));
        assert_eq!(sections, [(432, 32), (464, 84), (608, 18), (640, 144), (784, 4), (800, 44)]);
        assert_eq!(layout.total_bytes, 848, "the colour neighbours' room is not kept");
        assert_eq!(Layout::of_table(layout.sections, Counts::new(3, 1), shape).unwrap().total_bytes, 848);
        assert!(Layout::of_table(layout.sections, Counts::new(4, 1), shape).is_none());
        assert!(Layout::of_table(layout.sections, Counts::new(3, 2), shape).is_none());
        assert!(Layout::with_room(Counts::new(3, 0), u64::MAX, shape).is_none());
    }
}
