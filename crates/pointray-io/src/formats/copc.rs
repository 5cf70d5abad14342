//! COPC (https://copc.io): LAZ 1.4 whose points are stored in independently compressed
//! chunks, one per node of an octree that a hierarchy EVLR lists. The chunks are decoded in
//! parallel, one decoder per worker, after the hierarchy has been checked against the file
//! (`copc_hierarchy`). LAZ 1.4 compresses each field in a layer of its own, and the decoder
//! decompresses only the layers pointray reads (positions, intensity, classification,
//! colour); the GPS time, scan angle, user data, point source and flags layers are skipped.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use las::copc::Entry;
use las::{PointData, PointDataBuilder};
use laz::record::{LayeredPointRecordDecompressor, RecordDecompressor};
use laz::{DecompressionSelection, LazItem};
use rayon::prelude::*;

use super::copc_hierarchy::{ChunkRoom, point_chunks};
use super::las::{LasColumns, las_error, preflight, survive_decoder};
use crate::{IoError, PointCloud};

/// Where COPC puts its info VLR: first after the 375-byte LAS 1.4 header, whose user id
/// field starts 2 bytes in and whose record id follows it.
const INFO_USER_ID_AT: u64 = 375 + 2;
const INFO_RECORD_ID: u16 = 1;
const HIERARCHY_RECORD_ID: u16 = 1000;

/// Whether the LAS stream `read` is COPC (its first VLR is the COPC info VLR, as the
/// specification places it). Leaves the stream at its start.
pub(super) fn is_copc<R: Read + Seek>(read: &mut R) -> bool {
    let mut user_and_record = [0u8; 18];
    let found = read.seek(SeekFrom::Start(INFO_USER_ID_AT)).is_ok()
        && read.read_exact(&mut user_and_record).is_ok()
        && user_and_record.starts_with(b"copc\0")
        && u16::from_le_bytes([user_and_record[16], user_and_record[17]]) == INFO_RECORD_ID;
    read.seek(SeekFrom::Start(0)).map(|_| found).unwrap_or(false)
}

/// Reads a COPC file whole, its chunks decoded in parallel and put in file order. Points
/// and attributes come out as `read_las` gives them for the same file read as LAZ.
pub fn read_copc(path: &Path) -> Result<PointCloud, IoError> {
    let file = CopcFile::open(path)?;
    let mut columns = LasColumns::default();
    file.decode_each(file.chunks())?.iter().for_each(|chunk| columns.append(chunk));
    Ok(columns.into_point_cloud())
}

/// A COPC file whose hierarchy has been checked, ready to decode its chunks.
pub(super) struct CopcFile {
    path: PathBuf,
    header: las::Header,
    /// The chunks that hold points, in file order.
    chunks: Vec<Entry>,
}

impl CopcFile {
    pub(super) fn open(path: &Path) -> Result<Self, IoError> {
        let mut read = open(path)?;
        preflight(&mut read, path)?;
        let file_bytes = read.seek(SeekFrom::End(0)).map_err(|source| IoError::os(path, source))?;
        read.seek(SeekFrom::Start(0)).map_err(|source| IoError::os(path, source))?;
        let header = las::Header::new(&mut read).map_err(|error| las_error(path, error))?;
        let room = point_data_room(&mut read, file_bytes, path)?;
        let hierarchy_at = hierarchy_data_at(&mut read, path)?;
        let chunks = point_chunks(&header, hierarchy_at, &room, path)?;
        Ok(Self { path: path.to_path_buf(), header, chunks })
    }

    pub(super) fn path(&self) -> &Path {
        &self.path
    }

    pub(super) fn header(&self) -> &las::Header {
        &self.header
    }

    pub(super) fn chunks(&self) -> &[Entry] {
        &self.chunks
    }

    /// `chunks` decoded in parallel, one reader per worker, in their order.
    pub(super) fn decode_each(&self, chunks: &[Entry]) -> Result<Vec<PointData>, IoError> {
        let path = self.path.as_path();
        chunks
            .par_iter()
            .map_init(
                || ChunkDecoder::open(path, &self.header),
                |decoder, chunk| match decoder {
                    Ok(decoder) => decoder.decode(chunk, &self.header, path),
                    Err(error) => Err(IoError::malformed(path, format!("reopening failed: {error}"))),
                },
            )
            .collect()
    }
}

fn open(path: &Path) -> Result<BufReader<File>, IoError> {
    File::open(path).map(BufReader::new).map_err(|source| IoError::os(path, source))
}

/// The bytes chunks may occupy: from the header's offset to point data (u32 at byte 96) to
/// the first EVLR (u64 at byte 235; COPC keeps its hierarchy there) or the end of the file.
fn point_data_room<R: Read + Seek>(
    read: &mut R,
    file_bytes: u64,
    origin: &Path,
) -> Result<ChunkRoom, IoError> {
    let os = |source| IoError::os(origin, source);
    let data_start = u32::from_le_bytes(read_array_at(read, 96).map_err(os)?).into();
    let data_end = match u64::from_le_bytes(read_array_at(read, 235).map_err(os)?) {
        0 => file_bytes,
        evlr_start => evlr_start.min(file_bytes),
    };
    Ok(ChunkRoom { data_start, data_end })
}

/// EVLR header bytes: reserved (2), user id (16), record id (2), data length (8), description (32).
const EVLR_HEADER_BYTES: u64 = 60;

/// The file offset of the COPC hierarchy EVLR's data, found by walking the EVLRs from the
/// header's first-EVLR offset (u64 at byte 235) and count (u32 at byte 243); hierarchy
/// page offsets are file offsets into it.
fn hierarchy_data_at<R: Read + Seek>(read: &mut R, origin: &Path) -> Result<u64, IoError> {
    let os = |source| IoError::os(origin, source);
    let mut at = u64::from_le_bytes(read_array_at(read, 235).map_err(os)?);
    let count = u32::from_le_bytes(read_array_at(read, 243).map_err(os)?);
    for _ in 0..count {
        let user_id: [u8; 16] = read_array_at(read, at + 2).map_err(os)?;
        let record_id = u16::from_le_bytes(read_array_at(read, at + 18).map_err(os)?);
        if user_id.starts_with(b"copc\0") && record_id == HIERARCHY_RECORD_ID {
            return Ok(at + EVLR_HEADER_BYTES);
        }
        let length = u64::from_le_bytes(read_array_at(read, at + 20).map_err(os)?);
        at = at.saturating_add(EVLR_HEADER_BYTES).saturating_add(length);
    }
    Err(IoError::malformed(origin, "COPC hierarchy EVLR is missing"))
}

fn read_array_at<R: Read + Seek, const N: usize>(read: &mut R, at: u64) -> std::io::Result<[u8; N]> {
    let mut bytes = [0u8; N];
    read.seek(SeekFrom::Start(at))?;
    read.read_exact(&mut bytes)?;
    Ok(bytes)
}

/// The layers pointray reads: positions (x, y and the returns always come first), intensity,
/// classification and colour.
fn read_layers() -> DecompressionSelection {
    DecompressionSelection(
        DecompressionSelection::Z
            | DecompressionSelection::INTENSITY
            | DecompressionSelection::CLASSIFICATION
            | DecompressionSelection::RGB,
    )
}

/// A worker's decoder of a file's chunks.
struct ChunkDecoder {
    decompressor: LayeredPointRecordDecompressor<'static, BufReader<File>>,
    items: Vec<LazItem>,
}

impl ChunkDecoder {
    fn open(path: &Path, header: &las::Header) -> Result<Self, IoError> {
        let items = header.laz_vlr().map_err(|error| las_error(path, error))?.items().clone();
        Ok(Self { decompressor: LayeredPointRecordDecompressor::new(open(path)?), items })
    }

    fn decode(&mut self, chunk: &Entry, header: &las::Header, path: &Path) -> Result<PointData, IoError> {
        let record_bytes = usize::from(header.point_format().len());
        let mut records = vec![0u8; chunk.point_count as usize * record_bytes];
        let decompressed = survive_decoder(path, || {
            let laz = |error: laz::LasZipError| las_error(path, las::Error::from(error));
            self.decompressor
                .get_mut()
                .seek(SeekFrom::Start(chunk.offset))
                .map_err(|e| IoError::os(path, e))?;
            self.decompressor.reset();
            self.decompressor.set_fields_from(&self.items).map_err(laz)?;
            self.decompressor.set_selection(read_layers());
            self.decompressor.decompress_many(&mut records).map_err(|e| las_error(path, las::Error::from(e)))
        });
        decompressed?;
        PointDataBuilder::new()
            .for_header(header)
            .build_from_bytes(records)
            .map_err(|error| las_error(path, error))
    }
}
