//! The octree hierarchy of a COPC file (https://copc.io): its pages walked from the root
//! page the COPC info VLR locates, every reference and chunk checked against the file
//! before any chunk is decoded. The `las` crate trusts these values: a page that refers
//! back to an earlier one loops forever, and a chunk past the end of the file fails deep
//! in the decoder.

use std::collections::HashSet;
use std::path::Path;

use las::copc::{Entry, VoxelKey};

use crate::IoError;

/// Bytes of one hierarchy entry: key (4 × i32), offset (u64), byte size and point count (i32).
const ENTRY_BYTES: usize = 32;

/// Where a file's point chunks may lie: after the header and VLRs, before the EVLRs.
pub(super) struct ChunkRoom {
    pub(super) data_start: u64,
    pub(super) data_end: u64,
}

/// The entries of `header`'s hierarchy, whose data starts at file offset `hierarchy_at`,
/// that hold points, in file order, once every page reference resolves, no page is reached twice, every chunk lies within `room` and the
/// chunks hold the points the header declares.
pub(super) fn point_chunks(
    header: &las::Header,
    hierarchy_at: u64,
    room: &ChunkRoom,
    origin: &Path,
) -> Result<Vec<Entry>, IoError> {
    let root = root_page(header, origin)?;
    let pages = header
        .evlrs()
        .iter()
        .find(|evlr| evlr.is_copc_hierarchy())
        .ok_or_else(|| IoError::malformed(origin, "COPC hierarchy EVLR is missing"))?;
    let mut chunks = walk_pages(&pages.data, hierarchy_at, root, origin)?;
    chunks.iter().try_for_each(|chunk| check_chunk_within(chunk, room, origin))?;
    let record_bytes = u64::from(header.point_format().len());
    chunks.iter().try_for_each(|chunk| check_chunk_decodes(chunk, record_bytes, origin))?;
    check_points_declared(&chunks, header.number_of_points(), origin)?;
    chunks.sort_by_key(|chunk| chunk.offset);
    Ok(chunks)
}

/// Where the root hierarchy page lies in the file.
#[derive(Clone, Copy)]
struct RootPage {
    offset: u64,
    size: u64,
}

/// Byte of the root page's offset in the COPC info VLR's data, after the octree's centre,
/// half size and spacing (five f64); its size follows.
const ROOT_PAGE_AT: usize = 40;

/// The root page, from the COPC info VLR (the `las` crate keeps these fields private).
fn root_page(header: &las::Header, origin: &Path) -> Result<RootPage, IoError> {
    let info = header.vlrs().iter().find(|vlr| vlr.is_copc_info());
    let u64_at = |data: &[u8], at: usize| Some(u64::from_le_bytes(data.get(at..at + 8)?.try_into().ok()?));
    let root = info.and_then(|info| {
        Some(RootPage {
            offset: u64_at(&info.data, ROOT_PAGE_AT)?,
            size: u64_at(&info.data, ROOT_PAGE_AT + 8)?,
        })
    });
    root.ok_or_else(|| IoError::malformed(origin, "COPC info VLR is missing or too short"))
}

fn walk_pages(data: &[u8], hierarchy_at: u64, root: RootPage, origin: &Path) -> Result<Vec<Entry>, IoError> {
    let mut chunks = Vec::new();
    // The `las` crate's readers find pages by node, so a node may own one page only; and a
    // page reached twice would be walked forever.
    let (mut seen_offsets, mut seen_nodes) = (HashSet::new(), HashSet::new());
    let mut pending = vec![(VoxelKey::ROOT, root.offset, root.size)];
    while let Some((key, offset, size)) = pending.pop() {
        if !seen_offsets.insert(offset) || !seen_nodes.insert(key) {
            let problem = format!(
                "COPC hierarchy page of node {} at byte {offset} is reached twice, or its node owns \
                 another page (a cycle)",
                name(&key)
            );
            return Err(IoError::malformed(origin, problem));
        }
        for entry in
            page(data, hierarchy_at, key, offset, size, origin)?.chunks_exact(ENTRY_BYTES).map(parse_entry)
        {
            match entry.point_count {
                -1 => pending.push((entry.key, entry.offset, page_size(&entry, origin)?)),
                0 => {}
                count if count > 0 => chunks.push(entry),
                count => {
                    let problem = format!("COPC hierarchy node {} declares {count} points", name(&entry.key));
                    return Err(IoError::malformed(origin, problem));
                }
            }
        }
    }
    Ok(chunks)
}

/// The bytes of the page at file offset `offset`, within the hierarchy EVLR's data.
fn page<'a>(
    data: &'a [u8],
    hierarchy_at: u64,
    key: VoxelKey,
    offset: u64,
    size: u64,
    origin: &Path,
) -> Result<&'a [u8], IoError> {
    let start = offset.checked_sub(hierarchy_at);
    let range = start.and_then(|start| {
        Some(usize::try_from(start).ok()?..usize::try_from(start.checked_add(size)?).ok()?)
    });
    match range.and_then(|range| data.get(range)) {
        Some(bytes) if bytes.len() % ENTRY_BYTES == 0 => Ok(bytes),
        _ => {
            let problem = format!(
                "COPC hierarchy page of node {} at byte {offset} ({size} bytes) is not within the {}-byte hierarchy EVLR \
                 or not a whole number of entries",
                name(&key),
                data.len()
            );
            Err(IoError::malformed(origin, problem))
        }
    }
}

fn page_size(reference: &Entry, origin: &Path) -> Result<u64, IoError> {
    u64::try_from(reference.byte_size).map_err(|_| {
        let problem = format!(
            "COPC hierarchy page of node {} declares {} bytes",
            name(&reference.key),
            reference.byte_size
        );
        IoError::malformed(origin, problem)
    })
}

fn check_chunk_within(chunk: &Entry, room: &ChunkRoom, origin: &Path) -> Result<(), IoError> {
    let end = u64::try_from(chunk.byte_size).ok().and_then(|size| chunk.offset.checked_add(size));
    match end {
        Some(end) if chunk.offset >= room.data_start && end <= room.data_end => Ok(()),
        _ => {
            let problem = format!(
                "COPC chunk of node {} at byte {} ({} bytes) lies outside the point data (bytes {} to {}); \
                 the file is truncated or its hierarchy corrupt",
                name(&chunk.key),
                chunk.offset,
                chunk.byte_size,
                room.data_start,
                room.data_end
            );
            Err(IoError::malformed(origin, problem))
        }
    }
}

/// Decoded bytes a chunk may always declare, whatever its compressed size: about a million
/// points, more than COPC writers put in one node.
const ALWAYS_DECODABLE_BYTES: u64 = 64 << 20;

/// Decoded bytes per compressed byte past which a larger chunk is refused: far above what
/// real tiles reach (the Autzen tile's COPC copy, 4.7). The bound is there because the
/// decoder sizes its buffer by the declared count before reading, and a corrupt count would
/// ask for gigabytes.
const MAX_COMPRESSION_RATIO: u64 = 1024;

fn check_chunk_decodes(chunk: &Entry, record_bytes: u64, origin: &Path) -> Result<(), IoError> {
    let decoded = record_bytes.saturating_mul(chunk.point_count as u64);
    let compressed = u64::try_from(chunk.byte_size).unwrap_or(0);
    if decoded <= ALWAYS_DECODABLE_BYTES.max(compressed.saturating_mul(MAX_COMPRESSION_RATIO)) {
        return Ok(());
    }
    let problem = format!(
        "COPC chunk of node {} declares {} points ({decoded} bytes decoded) in {compressed} compressed bytes, \
         more than LAZ holds",
        name(&chunk.key),
        chunk.point_count
    );
    Err(IoError::malformed(origin, problem))
}

fn check_points_declared(chunks: &[Entry], declared: u64, origin: &Path) -> Result<(), IoError> {
    let held: u64 = chunks.iter().map(|chunk| chunk.point_count as u64).sum();
    if held == declared {
        return Ok(());
    }
    let problem = format!("COPC hierarchy holds {held} points but the header declares {declared}");
    Err(IoError::malformed(origin, problem))
}

fn parse_entry(bytes: &[u8]) -> Entry {
    let i32_at = |at: usize| i32::from_le_bytes(bytes[at..at + 4].try_into().expect("four bytes"));
    Entry {
        key: VoxelKey { l: i32_at(0), x: i32_at(4), y: i32_at(8), z: i32_at(12) },
        offset: u64::from_le_bytes(bytes[16..24].try_into().expect("eight bytes")),
        byte_size: i32_at(24),
        point_count: i32_at(28),
    }
}

/// A node's name as COPC tools print it: level-x-y-z.
fn name(key: &VoxelKey) -> String {
    format!("{}-{}-{}-{}", key.l, key.x, key.y, key.z)
}
