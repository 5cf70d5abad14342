//! Writing the patch store (`patch_store`'s layout) whole from a `PatchSet`: compact, as
//! `write` does, or with the full records, as tile files embed it.

use std::io::Write;
use std::path::Path;

use glam::DVec3;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS};

use crate::compact_patches::{
    BLOCK_PATCHES, BlockFrame, cold_problem, colors_of, frames_of, keeps_colors, patches_of,
    stored_origin_bounds,
};
use crate::patch_set::PatchSet;
use crate::patch_store::{
    Counts, Encoding, FORMAT_VERSION, HEADER_BYTES, Header, Layout, MAGIC, NEIGHBOR_SECTION, RecordShape,
    StoreError, StoredSettings,
};
use crate::prep_settings::PrepSettings;
use crate::scan_structure::ScanStructure;
use crate::stored_coarse::StoredCoarse;

/// Blocks encoded at a time while writing a whole set: a few MiB of compact records.
const CHUNK_BLOCKS: usize = 256;

/// What a store's header says of its patches.
#[derive(Clone, Debug, PartialEq)]
pub struct StoreSummary {
    pub settings: PrepSettings,
    pub offset: DVec3,
    pub patches: u64,
    /// The patches each section has room for (at least `patches`): a writer that knows only
    /// a bound on the count as it starts leaves room for that many.
    pub room: u64,
    /// Colour neighbours per patch: 0 or `COLOR_NEIGHBORS`.
    pub neighbor_slots: u32,
    pub scan: ScanStructure,
}

/// Writes `patches` compactly to `path` atomically (`pointray_io::write_atomically`): a
/// temporary file in the same directory, renamed over `path` only once complete. The store
/// records no scan structure.
pub fn write(path: &Path, patches: &PatchSet) -> Result<(), StoreError> {
    write_with_scan(path, patches, &ScanStructure::NotRecorded)
}

/// Writes `patches` compactly to `path` atomically, recording the `scan` structure prep found.
pub fn write_with_scan(path: &Path, patches: &PatchSet, scan: &ScanStructure) -> Result<(), StoreError> {
    let (summary, shape) = summary_of(patches, scan, Encoding::Compact, path)?;
    pointray_io::write_atomically(path, |file| write_contents(file, &summary, shape, patches))
        .map_err(|error| store_error(path, error))
}

/// Writes `patches` as a store of `encoding` into `out`; `path` names it in errors.
pub fn write_to(
    out: &mut impl Write,
    patches: &PatchSet,
    encoding: Encoding,
    path: &Path,
) -> Result<(), StoreError> {
    let (summary, shape) = summary_of(patches, &ScanStructure::NotRecorded, encoding, path)?;
    write_contents(out, &summary, shape, patches)
        .map_err(|source| StoreError::Io { path: path.to_path_buf(), source })
}

pub(crate) fn store_error(path: &Path, error: pointray_io::IoError) -> StoreError {
    match error {
        pointray_io::IoError::Os { path, source } => StoreError::Io { path, source },
        other => {
            StoreError::Io { path: path.to_path_buf(), source: std::io::Error::other(other.to_string()) }
        }
    }
}

fn overflow() -> std::io::Error {
    std::io::Error::other("the patch count overflows the store's length")
}

/// The header's summary of `patches` and the shape of their records, once they are seen to
/// be consistent and in range: a compact store would otherwise turn a NaN into a number.
fn summary_of(
    patches: &PatchSet,
    scan: &ScanStructure,
    encoding: Encoding,
    path: &Path,
) -> Result<(StoreSummary, RecordShape), StoreError> {
    let inconsistent = |problem| StoreError::InconsistentPatchSet { path: path.to_path_buf(), problem };
    let neighbor_slots = neighbor_slots(patches).map_err(inconsistent)?;
    let shape = match encoding {
        Encoding::Full => RecordShape::full(neighbor_slots),
        Encoding::Compact => {
            patches.check().map_err(inconsistent)?;
            let colors = keeps_colors(patches);
            if let Some(problem) = cold_problem(&patches.cold, colors) {
                return Err(inconsistent(problem));
            }
            RecordShape::compact(neighbor_slots, colors)
        }
    };
    let summary = StoreSummary {
        settings: patches.settings,
        offset: patches.offset,
        patches: patches.len() as u64,
        room: patches.len() as u64,
        neighbor_slots,
        scan: scan.clone(),
    };
    Ok((summary, shape))
}

/// How many colour neighbours each patch has (0 or `COLOR_NEIGHBORS`), or why the record
/// counts do not agree.
fn neighbor_slots(patches: &PatchSet) -> Result<u32, String> {
    let n = patches.len();
    let slots = if patches.color_neighbors.is_empty() { 0 } else { COLOR_NEIGHBORS };
    let lengths = [patches.aabbs.len(), patches.cold.len(), patches.color_neighbors.len()];
    if lengths != [n, n, n * slots] {
        return Err(format!(
            "{n} hot records, {} boxes, {} cold records and {} colour neighbours ({COLOR_NEIGHBORS} per patch wanted)",
            patches.aabbs.len(),
            patches.cold.len(),
            patches.color_neighbors.len()
        ));
    }
    Ok(slots as u32)
}

/// The header and the sections, then the checksum of both.
fn write_contents(
    file: &mut impl Write,
    summary: &StoreSummary,
    shape: RecordShape,
    patches: &PatchSet,
) -> std::io::Result<()> {
    let mut writer = ChecksummedWriter::new(file);
    let (frames, bounds, coarse) = match shape.encoding {
        Encoding::Compact => {
            let frames = frames_of(&patches.hot, &patches.cold);
            let coarse = StoredCoarse::of_blocks(&frames, &patches.hot, &patches.cold, shape.colors);
            (frames, stored_origin_bounds(&patches.hot), coarse)
        }
        Encoding::Full => (Vec::new(), patches.bounds(), StoredCoarse::default()),
    };
    let counts = Counts::new(summary.patches, coarse.records.len() as u64);
    let layout = Layout::with_room(counts, summary.room, shape).ok_or_else(overflow)?;
    writer.write_all(bytemuck::bytes_of(&header_for(summary, &layout, shape, (bounds, counts.coarse))))?;
    let mut position = HEADER_BYTES as u64;
    for (index, section) in layout.sections.iter().enumerate() {
        writer.write_zeros(section.offset - position)?;
        match (shape.encoding, index) {
            (_, NEIGHBOR_SECTION) => writer.write_all(bytemuck::cast_slice(&patches.color_neighbors))?,
            (Encoding::Full, 1) => writer.write_all(bytemuck::cast_slice(&patches.hot))?,
            (Encoding::Full, 2) => writer.write_all(bytemuck::cast_slice(&patches.cold))?,
            (Encoding::Compact, 0) => writer.write_all(bytemuck::cast_slice(&frames))?,
            (Encoding::Compact, 1) => write_compact_records(&mut writer, patches, &frames, true)?,
            (Encoding::Compact, 2) if shape.colors => {
                write_compact_records(&mut writer, patches, &frames, false)?
            }
            (Encoding::Compact, 4) => writer.write_all(bytemuck::cast_slice(&coarse.counts))?,
            (Encoding::Compact, 5) => writer.write_all(bytemuck::cast_slice(&coarse.records))?,
            _ => {}
        }
        position = section.offset + section.length;
    }
    let checksum = writer.hasher.finalize();
    writer.inner.write_all(&checksum.to_le_bytes())
}

/// The compact patches (`geometry`) or the colours of `patches`, a few blocks at a time.
fn write_compact_records<W: Write>(
    writer: &mut ChecksummedWriter<W>,
    patches: &PatchSet,
    frames: &[BlockFrame],
    geometry: bool,
) -> std::io::Result<()> {
    let chunk = CHUNK_BLOCKS * BLOCK_PATCHES;
    for (index, frames) in frames.chunks(CHUNK_BLOCKS).enumerate() {
        let range = index * chunk..((index + 1) * chunk).min(patches.len());
        let (hot, cold) = (&patches.hot[range.clone()], &patches.cold[range]);
        if geometry {
            writer.write_all(bytemuck::cast_slice(&patches_of(frames, hot, cold)))?;
        } else {
            writer.write_all(bytemuck::cast_slice(&colors_of(cold)))?;
        }
    }
    Ok(())
}

/// The header of `summary`'s patches, of which `bounds` bounds the origins as stored (the
/// boxes, for full records), and of their `coarse_patches`.
pub(crate) fn header_for(
    summary: &StoreSummary,
    layout: &Layout,
    shape: RecordShape,
    (bounds, coarse_patches): (Option<Aabb>, u64),
) -> Header {
    let bounds = bounds.unwrap_or_default();
    let (scan_kind, scan_counts, scan_reason) = Header::scan_fields(&summary.scan);
    let compact = shape.encoding == Encoding::Compact;
    Header {
        magic: MAGIC,
        version: FORMAT_VERSION,
        header_bytes: HEADER_BYTES as u32,
        point_count: summary.patches,
        offset: summary.offset.to_array(),
        bounds_min: bounds.min,
        bounds_max: bounds.max,
        sections: layout.sections,
        neighbor_slots: summary.neighbor_slots,
        settings: StoredSettings::of(&summary.settings),
        sensor: summary.settings.sensor.unwrap_or_default().to_array(),
        encoding: if compact { 0 } else { 1 },
        block_patches: if compact { BLOCK_PATCHES as u32 } else { 0 },
        color_columns: shape.colors.into(),
        scan_kind,
        scan_counts,
        scan_reason,
        coarse_patches,
    }
}

/// Passes bytes on and keeps a running CRC-32 of them.
struct ChecksummedWriter<W> {
    inner: W,
    hasher: crc32fast::Hasher,
}

impl<W: Write> ChecksummedWriter<W> {
    fn new(inner: W) -> Self {
        Self { inner, hasher: crc32fast::Hasher::new() }
    }

    fn write_all(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.hasher.update(bytes);
        self.inner.write_all(bytes)
    }

    /// Writes the zeros of the room between sections.
    fn write_zeros(&mut self, count: u64) -> std::io::Result<()> {
        let zeros = [0u8; 1 << 16];
        let mut left = count;
        while left > 0 {
            let piece = left.min(zeros.len() as u64) as usize;
            self.write_all(&zeros[..piece])?;
            left -= piece as u64;
        }
        Ok(())
    }
}
