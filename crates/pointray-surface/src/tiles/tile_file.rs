//! One tile's patches in a file of their own, as `pointray prep --tile I --of N` writes it
//! and a merge reads it: the tile's place, each patch's input point, the colour neighbours
//! by input point (patch indices exist only once all tiles are merged), and the patches as
//! an embedded patch store without colour neighbours.
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 8 | magic `b"PRTILE\0\0"` |
//! | 8 | 4 | version, u32 = 3 |
//! | 12 | 4 | tile index, u32 |
//! | 16 | 4 | tile count, u32 |
//! | 20 | 4 | colour neighbours per patch `m`, u32 |
//! | 24 | 8 | points in the whole input, u64 |
//! | 32 | 8 | patches `n`, u64 |
//! | 40 | 4 n | each patch's input point, u32 |
//! | 40 + 4 n | 4 m n | colour neighbours as input points, u32 (`0xffffffff`: none) |
//! | then | | a patch store (`patch_store`) of the patches with their full records, `m` = 0 |
//! | end - 4 | 4 | CRC-32 (IEEE) of every byte before it |

use std::io::Read;
use std::path::Path;

use bytemuck::{Pod, Zeroable};
use pointray_patches::patch_store::{self, Encoding, FullRecords};

use crate::tiles::stream_error::StreamError;
use crate::tiles::tiled_prep::TilePatches;

const MAGIC: [u8; 8] = *b"PRTILE\0\0";
/// Version 3 embeds a version 9 store of full records without their boxes (48 bytes a patch
/// with its input point, where version 2's boxes made it 72), which the merge quantises once.
const VERSION: u32 = 3;
const HEADER_BYTES: usize = size_of::<TileHeader>();

/// Where a tile belongs.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct TileHeader {
    magic: [u8; 8],
    version: u32,
    pub index: u32,
    pub count: u32,
    pub neighbor_slots: u32,
    pub input_points: u64,
    pub patches: u64,
}

/// Writes tile `index` of `count` of an input of `input_points` points, atomically.
pub fn write_tile_file(
    path: &Path,
    tile: TilePatches,
    (index, count): (usize, usize),
    input_points: u64,
) -> Result<(), StreamError> {
    let TilePatches { mut patches, sources } = tile;
    let neighbors = std::mem::take(&mut patches.color_neighbors);
    let header = TileHeader {
        magic: MAGIC,
        version: VERSION,
        index: index as u32,
        count: count as u32,
        neighbor_slots: (neighbors.len().checked_div(sources.len()).unwrap_or(0)) as u32,
        input_points,
        patches: sources.len() as u64,
    };
    let mut bytes = bytemuck::bytes_of(&header).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&sources));
    bytes.extend_from_slice(bytemuck::cast_slice(&neighbors));
    patch_store::write_to(&mut bytes, &patches, Encoding::Full, path)?;
    let checksum = crc32fast::hash(&bytes);
    bytes.extend(checksum.to_le_bytes());
    pointray_io::write_atomically(path, |file| std::io::Write::write_all(file, &bytes))?;
    Ok(())
}

/// The header alone, checked for magic and version.
pub fn read_tile_header(path: &Path) -> Result<TileHeader, StreamError> {
    let mut bytes = [0u8; HEADER_BYTES];
    let mut file = std::fs::File::open(path).map_err(|e| StreamError::scratch(path, e))?;
    file.read_exact(&mut bytes).map_err(|_| bad(path, "not a pointray tile file (too short)"))?;
    checked_header(&bytes, path)
}

/// One tile's records as a tile file holds them: without boxes, which a merge has no use for.
#[derive(Clone, Debug, PartialEq)]
pub struct TileRecords {
    pub records: FullRecords,
    /// Colour neighbours named by input point.
    pub color_neighbors: Vec<u32>,
    /// Each patch's input point.
    pub sources: Vec<u32>,
}

/// A whole tile file, checked.
pub fn read_tile_file(path: &Path) -> Result<(TileHeader, TileRecords), StreamError> {
    let bytes = std::fs::read(path).map_err(|e| StreamError::scratch(path, e))?;
    let header = checked_header(bytes.get(..HEADER_BYTES).unwrap_or(&[]), path)?;
    let (n, m) = (header.patches as usize, header.neighbor_slots as usize);
    let store_start = n
        .checked_mul(4 * (1 + m))
        .and_then(|tables| tables.checked_add(HEADER_BYTES))
        .filter(|&start| start + 4 <= bytes.len())
        .ok_or_else(|| bad(path, "truncated: shorter than its header's patch count implies"))?;
    let (body, checksum) = bytes.split_at(bytes.len() - 4);
    if crc32fast::hash(body).to_le_bytes() != checksum {
        return Err(bad(path, "corrupted: checksum mismatch"));
    }
    let records = patch_store::read_full_records(&body[store_start..], path)?;
    if records.hot.len() != n {
        return Err(bad(path, "its patches do not match its header's count"));
    }
    let table = |start: usize, len: usize| bytemuck::pod_collect_to_vec::<u8, u32>(&body[start..start + len]);
    let sources = table(HEADER_BYTES, 4 * n);
    let color_neighbors = table(HEADER_BYTES + 4 * n, 4 * m * n);
    if sources.iter().any(|&s| u64::from(s) >= header.input_points) {
        return Err(bad(path, "a patch names a point beyond the input's count"));
    }
    Ok((header, TileRecords { records, color_neighbors, sources }))
}

fn checked_header(bytes: &[u8], path: &Path) -> Result<TileHeader, StreamError> {
    let header: TileHeader = bytemuck::try_pod_read_unaligned(bytes)
        .map_err(|_| bad(path, "not a pointray tile file (too short)"))?;
    if header.magic != MAGIC {
        return Err(bad(path, "not a pointray tile file (wrong magic)"));
    }
    if header.version != VERSION {
        let problem = format!(
            "tile file version {}, this build reads version {VERSION}: prep the tile again",
            header.version
        );
        return Err(bad(path, &problem));
    }
    if header.index >= header.count || !matches!(header.neighbor_slots, 0 | 12) {
        return Err(bad(path, "malformed tile header"));
    }
    Ok(header)
}

fn bad(path: &Path, problem: &str) -> StreamError {
    StreamError::BadTile { path: path.to_path_buf(), problem: problem.to_string() }
}
