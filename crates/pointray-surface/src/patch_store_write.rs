//! Writing the patch store (`patch_store`'s layout): whole from a `PatchSet`, or section by
//! section from parts that never sit in memory together (the tiles of a merge).

use std::fs::File;
use std::io::Write;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS};
use rayon::prelude::*;

use crate::parallel_checksum;
use crate::patch_set::PatchSet;
use crate::patch_store::{
    FORMAT_VERSION, HEADER_BYTES, Header, Layout, MAGIC, SECTION_ALIGNMENT, SECTION_COUNT, Section,
    StoreError, StoredSettings,
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
    /// Colour neighbours per patch: 0 or `COLOR_NEIGHBORS`.
    pub neighbor_slots: u32,
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

/// Writes a store of `summary`'s patches to `path` atomically from the files `sections` that
/// hold its sections (0: boxes, 1: hot, 2: cold, 3: colour neighbours), copied and
/// checksummed a piece per thread at a time; `neighbor` turns each colour neighbour as its
/// file holds it into the store's.
pub fn write_section_files(
    path: &Path,
    summary: &StoreSummary,
    sections: &[PathBuf; SECTION_COUNT],
    neighbor: impl Fn(u32) -> u32 + Sync,
) -> Result<(), StoreError> {
    let layout = Layout::new(summary.patches, summary.neighbor_slots)
        .ok_or_else(|| StoreError::Io { path: path.to_path_buf(), source: overflow() })?;
    pointray_io::write_atomically(path, |writer| {
        let header = header_for(summary, &layout);
        writer.write_all(bytemuck::bytes_of(&header))?;
        writer.flush()?;
        let store = writer.get_ref();
        let mut hasher = crc32fast::Hasher::new();
        hasher.update(bytemuck::bytes_of(&header));
        let mut position = HEADER_BYTES as u64;
        for (index, (section, source)) in layout.sections.iter().zip(sections).enumerate() {
            // The padding is never written: the file reads zeros there.
            hasher.update(&[0u8; SECTION_ALIGNMENT][..(section.offset - position) as usize]);
            let source = File::open(source)?;
            let found = source.metadata()?.len();
            if found != section.length {
                return Err(wrong_length(index, found, section.length));
            }
            let words = (index == NEIGHBOR_SECTION).then_some(&neighbor as &(dyn Fn(u32) -> u32 + Sync));
            let pieces = (0..section.length.div_ceil(COPY_PIECE_BYTES))
                .into_par_iter()
                .map(|piece| copy_piece(&source, (store, section), piece, words))
                .collect::<std::io::Result<Vec<_>>>()?;
            pieces.iter().for_each(|piece| hasher.combine(piece));
            position = section.offset + section.length;
        }
        store.write_all_at(&hasher.finalize().to_le_bytes(), position)
    })
    .map_err(|error| store_error(path, error))
}

/// The section of colour neighbours, whose words name patches.
const NEIGHBOR_SECTION: usize = 3;

/// Bytes of a section copied at a time by one thread (a multiple of every record's size).
const COPY_PIECE_BYTES: u64 = 1 << 20;

/// Copies piece `piece` of `section` from `source` into `store`, its words mapped through
/// `words` when given, and returns the piece's checksum.
fn copy_piece(
    source: &File,
    (store, section): (&File, &Section),
    piece: u64,
    words: Option<&(dyn Fn(u32) -> u32 + Sync)>,
) -> std::io::Result<crc32fast::Hasher> {
    let start = piece * COPY_PIECE_BYTES;
    let mut bytes = vec![0u8; (COPY_PIECE_BYTES.min(section.length - start)) as usize];
    source.read_exact_at(&mut bytes, start)?;
    if let Some(map) = words {
        for word in bytes.chunks_exact_mut(4) {
            let mapped = map(u32::from_le_bytes([word[0], word[1], word[2], word[3]]));
            word.copy_from_slice(&mapped.to_le_bytes());
        }
    }
    store.write_all_at(&bytes, section.offset + start)?;
    Ok(parallel_checksum::piece_hasher(&bytes))
}

fn store_error(path: &Path, error: pointray_io::IoError) -> StoreError {
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
    let layout = Layout::new(summary.patches, summary.neighbor_slots).ok_or_else(overflow)?;
    writer.write_all(bytemuck::bytes_of(&header_for(summary, &layout)))?;
    let mut position = HEADER_BYTES as u64;
    for (index, section) in layout.sections.iter().enumerate().take(SECTION_COUNT) {
        let padding = [0u8; SECTION_ALIGNMENT];
        writer.write_all(&padding[..(section.offset - position) as usize])?;
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

fn header_for(summary: &StoreSummary, layout: &Layout) -> Header {
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
}
