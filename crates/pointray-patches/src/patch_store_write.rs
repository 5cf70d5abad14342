//! Writing the patch store (`patch_store`'s layout): whole from a `PatchSet`, or section by
//! section from parts that never sit in memory together (the tiles of a merge).

use std::io::Write;
use std::path::Path;

use glam::DVec3;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS};

use crate::patch_set::PatchSet;
use crate::patch_store::{
    FORMAT_VERSION, HEADER_BYTES, Header, Layout, MAGIC, SECTION_COUNT, StoreError, StoredSettings,
};
use crate::prep_settings::PrepSettings;

/// What a store's header says of its patches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StoreSummary {
    pub settings: PrepSettings,
    pub offset: DVec3,
    /// The union of all patch boxes (`None` for no patches).
    pub bounds: Option<Aabb>,
    pub patches: u64,
    /// The patches each section has room for (at least `patches`): a writer that knows only
    /// a bound on the count as it starts leaves room for that many.
    pub room: u64,
    /// Colour neighbours per patch: 0 or `COLOR_NEIGHBORS`.
    pub neighbor_slots: u32,
}

impl StoreSummary {
    /// Counts `set`'s patches after those counted so far, and takes in their boxes.
    pub fn add(&mut self, set: &PatchSet) {
        self.patches += set.len() as u64;
        self.bounds = match (self.bounds, set.bounds()) {
            (Some(a), Some(b)) => Some(a.union(&b)),
            (a, b) => a.or(b),
        };
    }
}

/// Receives a section's bytes, in as many pieces as its writer likes.
pub type SectionSink<'a> = dyn FnMut(&[u8]) -> std::io::Result<()> + 'a;

/// Writes `patches` to `path` atomically (`pointray_io::write_atomically`): a temporary file
/// in the same directory, renamed over `path` only once complete.
pub fn write(path: &Path, patches: &PatchSet) -> Result<(), StoreError> {
    let summary = summary_of(patches, path)?;
    write_sections(path, &summary, |section, sink| sink(section_bytes(patches, section)))
}

/// Writes `patches` as a store into `out`; `path` names it in errors.
pub fn write_to(out: &mut impl Write, patches: &PatchSet, path: &Path) -> Result<(), StoreError> {
    let summary = summary_of(patches, path)?;
    write_contents(out, &summary, &mut |section, sink| sink(section_bytes(patches, section)))
        .map_err(|source| StoreError::Io { path: path.to_path_buf(), source })
}

/// Writes a store of `summary`'s patches to `path` atomically, `fill` handing each section's
/// bytes (0: boxes, 1: hot, 2: cold, 3: colour neighbours) to the sink it is given; a
/// section of the wrong length fails the write.
pub fn write_sections(
    path: &Path,
    summary: &StoreSummary,
    mut fill: impl FnMut(usize, &mut SectionSink) -> std::io::Result<()>,
) -> Result<(), StoreError> {
    pointray_io::write_atomically(path, |file| write_contents(file, summary, &mut fill))
        .map_err(|error| store_error(path, error))
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

fn wrong_length(index: usize, found: u64, wanted: u64) -> std::io::Error {
    std::io::Error::other(format!("section {index} has {found} bytes, its patches need {wanted}"))
}

fn summary_of(patches: &PatchSet, path: &Path) -> Result<StoreSummary, StoreError> {
    let neighbor_slots = neighbor_slots(patches)
        .map_err(|problem| StoreError::InconsistentPatchSet { path: path.to_path_buf(), problem })?;
    Ok(StoreSummary {
        settings: patches.settings,
        offset: patches.offset,
        bounds: patches.bounds(),
        patches: patches.len() as u64,
        room: patches.len() as u64,
        neighbor_slots,
    })
}

fn section_bytes(patches: &PatchSet, section: usize) -> &[u8] {
    match section {
        0 => bytemuck::cast_slice(&patches.aabbs),
        1 => bytemuck::cast_slice(&patches.hot),
        2 => bytemuck::cast_slice(&patches.cold),
        _ => bytemuck::cast_slice(&patches.color_neighbors),
    }
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
    fill: &mut impl FnMut(usize, &mut SectionSink) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let mut writer = ChecksummedWriter::new(file);
    let layout =
        Layout::with_room(summary.patches, summary.room, summary.neighbor_slots).ok_or_else(overflow)?;
    writer.write_all(bytemuck::bytes_of(&header_for(summary, &layout)))?;
    let mut position = HEADER_BYTES as u64;
    for (index, section) in layout.sections.iter().enumerate().take(SECTION_COUNT) {
        writer.write_zeros(section.offset - position)?;
        let mut written = 0u64;
        fill(index, &mut |bytes: &[u8]| {
            written += bytes.len() as u64;
            writer.write_all(bytes)
        })?;
        if written != section.length {
            return Err(wrong_length(index, written, section.length));
        }
        position = section.offset + section.length;
    }
    let checksum = writer.hasher.finalize();
    writer.inner.write_all(&checksum.to_le_bytes())
}

pub(crate) fn header_for(summary: &StoreSummary, layout: &Layout) -> Header {
    let bounds = summary.bounds.unwrap_or_default();
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
