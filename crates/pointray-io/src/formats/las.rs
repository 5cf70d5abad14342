//! LAS 1.0–1.4 and LAZ (LASzip-compressed LAS), read with the `las` crate.
//!
//! Coordinates are decoded to f64 with the header's scale and offset, so geo-referenced
//! tiles (coordinates near 10^6) keep the file's full precision.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::panic::AssertUnwindSafe;
use std::path::Path;

use glam::DVec3;
use las::{PointData, PointDataBuilder};

use super::copc::{is_copc, read_copc};
use super::intensity::normalise_intensities;
use crate::{IoError, PointCloud};

const SUPPORTED: &str = "LAS 1.0-1.4 with point formats 0-10, uncompressed or LAZ-compressed";

/// Bytes decoded per batch: big enough to amortise the per-call cost, small enough that a
/// header that lies about its point count or record length cannot make us allocate much more
/// than the data holds (the `las` crate sizes its buffer before reading).
const BATCH_BYTES: u64 = 4 << 20;

/// Reads a `.las` or `.laz` file. Colours are scaled to 8 bits (files that store 8-bit values
/// in the 16-bit fields are detected and kept as they are); intensities are normalised to
/// [0, 1]; classifications are the ASPRS codes (5 bits before point format 6, 8 bits from it
/// on). Every LAS point has these fields, filled or not: an all-zero colour, intensity or
/// classification (class 0, "never classified") is reported as absent. COPC files, whose
/// chunks can be decoded independently, are decoded in parallel.
pub fn read_las(path: &Path) -> Result<PointCloud, IoError> {
    let file = File::open(path).map_err(|source| IoError::os(path, source))?;
    let mut read = BufReader::new(file);
    if is_copc(&mut read) {
        return read_copc(path);
    }
    read_las_from(read, path)
}

/// Reads LAS or LAZ data from any seekable stream; `origin` names it in errors.
pub fn read_las_from<R>(mut read: R, origin: &Path) -> Result<PointCloud, IoError>
where
    R: Read + Seek + Send + Sync + 'static,
{
    preflight(&mut read, origin)?;
    survive_decoder(origin, || decode(read, origin))
}

/// A reader positioned at the first point of the file at `path`, once the preflight passed.
pub(super) fn open_reader(path: &Path) -> Result<las::Reader, IoError> {
    let mut read = BufReader::new(File::open(path).map_err(|source| IoError::os(path, source))?);
    preflight(&mut read, path)?;
    survive_decoder(path, || las::Reader::new(read).map_err(|error| las_error(path, error)))
}

/// The `laz` decoder still indexes and slices on values from corrupt data in ways the
/// preflight cannot foresee (fuzzing found several); its panics become errors here.
pub(super) fn survive_decoder<T>(
    origin: &Path,
    decode: impl FnOnce() -> Result<T, IoError>,
) -> Result<T, IoError> {
    std::panic::catch_unwind(AssertUnwindSafe(decode))
        .unwrap_or_else(|_| Err(IoError::malformed(origin, "LAS/LAZ decoder failed on corrupt point data")))
}

/// Points per batch for the reader's point format.
pub(super) fn batch_points(header: &las::Header) -> u64 {
    (BATCH_BYTES / u64::from(header.point_format().len()).max(1)).max(1)
}

fn decode<R>(read: R, origin: &Path) -> Result<PointCloud, IoError>
where
    R: Read + Seek + Send + Sync + 'static,
{
    let mut reader = las::Reader::new(read).map_err(|error| las_error(origin, error))?;
    let declared = reader.header().number_of_points();
    let mut columns = LasColumns::default();
    let batch_points = batch_points(reader.header());
    let mut batch = PointDataBuilder::new().for_header(reader.header()).build();
    loop {
        let read = reader.fill_points(batch_points, &mut batch).map_err(|error| las_error(origin, error))?;
        if read == 0 {
            break;
        }
        columns.append(&batch);
    }
    if columns.positions.len() as u64 != declared {
        let problem =
            format!("header declares {declared} points but the data holds {}", columns.positions.len());
        return Err(IoError::malformed(origin, problem));
    }
    Ok(columns.into_point_cloud())
}

/// Checks what the `las` and `laz` crates would otherwise trust: EVLR lengths they allocate
/// before reading (a corrupt one asks for gigabytes), a LAZ item list they
/// index without looking (an empty one panics) and a chunk count they reserve room for
/// before reading (a corrupt one asks for gigabytes). Leaves the stream at its start.
pub(super) fn preflight<R: Read + Seek>(read: &mut R, origin: &Path) -> Result<(), IoError> {
    check_evlr_lengths(read, origin)?;
    check_declared_points(read, origin)?;
    read.seek(SeekFrom::Start(0)).map_err(|source| IoError::os(origin, source))?;
    let header = las::Header::new(&mut *read).map_err(|error| las_error(origin, error))?;
    check_version(&header, origin)?;
    check_transforms(&header, origin)?;
    if header.point_format().is_compressed {
        check_laszip_items(&header, origin)?;
        let stream_bytes = read.seek(SeekFrom::End(0)).map_err(|source| IoError::os(origin, source))?;
        // A chunk table we cannot locate is left to the `laz` crate, which reports it.
        if let Ok(chunks) = laz_chunk_count(read)
            && chunks > stream_bytes
        {
            let problem = format!("LAZ chunk table declares {chunks} chunks in a {stream_bytes}-byte file");
            return Err(IoError::malformed(origin, problem));
        }
        // Reads the chunk table, so only after its count is known to be sane.
        check_laz_chunks_cover_points(read, &header, origin)?;
    }
    read.seek(SeekFrom::Start(0)).map(drop).map_err(|source| IoError::os(origin, source))
}

/// Refuses a point count that the file cannot hold, from the header's raw fields: the `las`
/// crate multiplies it by the record length unchecked (2^60 points overflow), and a streamed
/// read sizes its scratch files by it. An uncompressed file must hold every record it
/// declares. Headers too short for the fields are left to the `las` crate, which reports them.
fn check_declared_points<R: Read + Seek>(read: &mut R, origin: &Path) -> Result<(), IoError> {
    let Ok(fields) = RawCount::read(read) else { return Ok(()) };
    let stream_bytes = read.seek(SeekFrom::End(0)).map_err(|source| IoError::os(origin, source))?;
    let available = if fields.compressed { u64::MAX } else { stream_bytes.saturating_sub(fields.data_start) };
    match fields.points.checked_mul(fields.record) {
        Some(needed) if needed <= available => Ok(()),
        _ => Err(IoError::malformed(
            origin,
            format!(
                "the header declares {} points of {} bytes, more than the file's {stream_bytes} bytes hold",
                fields.points, fields.record
            ),
        )),
    }
}

/// The header fields that say how many bytes of points follow.
struct RawCount {
    points: u64,
    record: u64,
    data_start: u64,
    compressed: bool,
}

impl RawCount {
    fn read<R: Read + Seek>(read: &mut R) -> std::io::Result<Self> {
        let [_, minor] = read_array_at(read, 24)?;
        let data_start = u64::from(u32::from_le_bytes(read_array_at(read, 96)?));
        let [format] = read_array_at(read, 104)?;
        let record = u64::from(u16::from_le_bytes(read_array_at(read, 105)?));
        let legacy = u64::from(u32::from_le_bytes(read_array_at(read, 107)?));
        // LAS 1.4 keeps a 64-bit count, which readers take when the legacy one is 0.
        let points =
            if minor >= 4 && legacy == 0 { u64::from_le_bytes(read_array_at(read, 247)?) } else { legacy };
        // LASzip marks compressed point formats with bit 7 (or bit 6).
        Ok(Self { points, record, data_start, compressed: format & 0xc0 != 0 })
    }
}

/// Size of an extended VLR's header; its u64 data length sits 20 bytes in.
const EVLR_HEADER_BYTES: u64 = 60;

/// Refuses LAS 1.4 EVLRs whose declared lengths run past the end of the stream. Headers
/// too short to hold the EVLR fields are left to the `las` crate, which reports them.
fn check_evlr_lengths<R: Read + Seek>(read: &mut R, origin: &Path) -> Result<(), IoError> {
    let os = |source| IoError::os(origin, source);
    let stream_bytes = read.seek(SeekFrom::End(0)).map_err(os)?;
    let Ok(version) = read_array_at::<_, 2>(read, 24) else { return Ok(()) };
    let (Ok(start), Ok(count)) = (read_array_at::<_, 8>(read, 235), read_array_at::<_, 4>(read, 243)) else {
        return Ok(());
    };
    if version != [1, 4] {
        return Ok(());
    }
    let mut at = u64::from_le_bytes(start);
    for _ in 0..u32::from_le_bytes(count) {
        let Ok(length) = read_array_at::<_, 8>(read, at.saturating_add(20)).map(u64::from_le_bytes) else {
            return Ok(());
        };
        let data_at = at.saturating_add(EVLR_HEADER_BYTES);
        if length > stream_bytes.saturating_sub(data_at) {
            let problem = format!("EVLR at byte {at} declares {length} bytes in a {stream_bytes}-byte file");
            return Err(IoError::malformed(origin, problem));
        }
        at = data_at + length;
    }
    Ok(())
}

fn read_array_at<R: Read + Seek, const N: usize>(read: &mut R, at: u64) -> std::io::Result<[u8; N]> {
    let mut bytes = [0u8; N];
    read.seek(SeekFrom::Start(at))?;
    read.read_exact(&mut bytes)?;
    Ok(bytes)
}

fn check_laszip_items(header: &las::Header, origin: &Path) -> Result<(), IoError> {
    let laszip = header.laz_vlr().map_err(|error| las_error(origin, error))?;
    if laszip.items().is_empty() {
        return Err(IoError::malformed(origin, "LAZ header (LASzip VLR) describes no point items"));
    }
    // The decoder splits each record by the sizes its item types imply, without checking
    // that they add up to the record it is handed.
    let record_bytes = u64::from(header.point_format().len());
    let items_bytes: u64 = laszip.items().iter().map(|item| laz_item_bytes(item.item_type())).sum();
    if items_bytes != record_bytes {
        let problem = format!(
            "LAZ items describe {items_bytes}-byte points but the header's point format has {record_bytes}"
        );
        return Err(IoError::malformed(origin, problem));
    }
    Ok(())
}

/// Bytes of a point record that a LAZ item decodes (LASzip's fixed sizes per item type).
fn laz_item_bytes(item: laz::LazItemType) -> u64 {
    use laz::LazItemType::*;
    match item {
        Byte(bytes) | Byte14(bytes) => bytes.into(),
        Point10 => 20,
        GpsTime => 8,
        RGB12 | RGB14 => 6,
        RGBNIR14 => 8,
        WavePacket13 | WavePacket14 => 29,
        Point14 => 30,
    }
}

/// With variable-size chunks the `laz` crate looks up each chunk's point count in the chunk
/// table without checking that the table has that many entries; refuse tables that cover
/// fewer points than the header declares. Tables that cannot be read are left to the `laz`
/// crate, which reports them.
fn check_laz_chunks_cover_points<R: Read + Seek>(
    read: &mut R,
    header: &las::Header,
    origin: &Path,
) -> Result<(), IoError> {
    let laszip = header.laz_vlr().map_err(|error| las_error(origin, error))?;
    if !laszip.uses_variable_size_chunks() {
        return Ok(());
    }
    let Ok(data_start) = read_array_at(read, 96).map(u32::from_le_bytes) else { return Ok(()) };
    if read.seek(SeekFrom::Start(data_start.into())).is_err() {
        return Ok(());
    }
    let Ok(table) = laz::laszip::ChunkTable::read_from(&mut *read, &laszip) else { return Ok(()) };
    let covered = (0..table.len()).fold(0u64, |sum, chunk| sum.saturating_add(table[chunk].point_count));
    let declared = header.number_of_points();
    if covered < declared {
        let problem = format!("LAZ chunk table covers {covered} points but the header declares {declared}");
        return Err(IoError::malformed(origin, problem));
    }
    Ok(())
}

/// The chunk count of a LAZ stream. Follows LASzip: the point data starts with the chunk
/// table's offset, or with -1 and the offset in the last 8 bytes.
fn laz_chunk_count<R: Read + Seek>(read: &mut R) -> std::io::Result<u64> {
    let data_start = i64::from(u32::from_le_bytes(read_array_at(read, 96)?));
    let mut table_at = read_i64_at(read, SeekFrom::Start(data_start as u64))?;
    if table_at <= data_start {
        table_at = read_i64_at(read, SeekFrom::End(-8))?;
    }
    if table_at <= data_start {
        return Err(std::io::ErrorKind::NotFound.into());
    }
    let version_and_count = read_i64_at(read, SeekFrom::Start(table_at as u64))?;
    Ok((version_and_count as u64) >> 32)
}

fn read_i64_at<R: Read + Seek>(read: &mut R, at: SeekFrom) -> std::io::Result<i64> {
    let at = read.seek(at)?;
    read_array_at(read, at).map(i64::from_le_bytes)
}

fn check_version(header: &las::Header, origin: &Path) -> Result<(), IoError> {
    let version = header.version();
    if version.major == 1 && version.minor <= 4 {
        return Ok(());
    }
    Err(IoError::Unsupported {
        path: origin.into(),
        what: format!("LAS version {}.{}", version.major, version.minor),
        supported: SUPPORTED.into(),
    })
}

/// The smallest scale factor taken for a real one: a picometre in metres. Smaller ones (0,
/// 1e-300) put every point at one coordinate, and the cloud would be prepped as a plane.
const MIN_SCALE: f64 = 1e-12;

/// Refuses a scale or offset that cannot place the points, naming the header field: a scale
/// that is not finite or below `MIN_SCALE` in size, or an offset so large (1e300) that f64
/// cannot tell apart coordinates a scale step apart there.
fn check_transforms(header: &las::Header, origin: &Path) -> Result<(), IoError> {
    let transforms = header.transforms();
    for (axis, transform) in [("x", transforms.x), ("y", transforms.y), ("z", transforms.z)] {
        let (scale, offset) = (transform.scale.abs(), transform.offset);
        if !(scale.is_finite() && scale >= MIN_SCALE) {
            let problem = format!(
                "the header's {axis} scale factor is {}, which puts every point at one {axis}; \
                 scale factors are steps of at least {MIN_SCALE} (0.01 or 0.001 are usual)",
                transform.scale
            );
            return Err(IoError::malformed(origin, problem));
        }
        // The largest coordinate the field can hold, and f64's step there.
        let largest = offset.abs() + scale * f64::from(u32::MAX);
        if !(largest.is_finite() && largest.next_up() - largest <= scale) {
            let problem = format!(
                "the header's {axis} offset is {offset}, too large for its scale factor {}: \
                 f64 cannot tell apart points a step apart there",
                transform.scale
            );
            return Err(IoError::malformed(origin, problem));
        }
    }
    Ok(())
}

/// Sorts the `las` crate's errors into "we cannot read this variant" and "this file is broken".
pub(super) fn las_error(origin: &Path, error: las::Error) -> IoError {
    let unsupported =
        |what: String| IoError::Unsupported { path: origin.into(), what, supported: SUPPORTED.into() };
    match error {
        las::Error::InvalidPointFormatNumber(number) => unsupported(format!("LAS point format {number}")),
        // `Format` displays itself as "point format N".
        las::Error::InvalidPointFormat(format) => unsupported(format!("LAS {format}")),
        las::Error::UnsupportedFormat { version, format } => {
            unsupported(format!("{format} in LAS version {version}"))
        }
        las::Error::LasZipError(error) => {
            IoError::malformed(origin, format!("LAZ decompression failed: {error}"))
        }
        las::Error::Io(source) if source.kind() == std::io::ErrorKind::UnexpectedEof => {
            IoError::malformed(origin, "LAS data is truncated (file ends before the declared points)")
        }
        other => IoError::malformed(origin, format!("not a readable LAS/LAZ file: {other}")),
    }
}

/// The columns we keep, filled batch by batch.
#[derive(Default)]
pub(super) struct LasColumns {
    positions: Vec<DVec3>,
    raw_intensities: Vec<f64>,
    raw_colors: Option<Vec<[u16; 3]>>,
    classifications: Vec<u8>,
}

impl LasColumns {
    pub(super) fn append(&mut self, batch: &PointData) {
        self.positions.extend(batch.x().zip(batch.y()).zip(batch.z()).map(|((x, y), z)| DVec3::new(x, y, z)));
        self.raw_intensities.extend(batch.intensity().map(f64::from));
        self.classifications.extend(batch.classification());
        if let Some(rgb) = batch.rgb() {
            self.raw_colors.get_or_insert_with(Vec::new).extend(rgb.map(|(r, g, b)| [r, g, b]));
        }
    }

    pub(super) fn into_point_cloud(self) -> PointCloud {
        PointCloud {
            intensities: normalise_intensities(&self.raw_intensities),
            colors: self.raw_colors.as_deref().and_then(colors_to_8_bit),
            classifications: self
                .classifications
                .iter()
                .any(|&class| class != 0)
                .then_some(self.classifications),
            ..PointCloud::from_positions(self.positions)
        }
    }
}

/// LAS stores colour in 16 bits, but many writers put 8-bit values there unscaled: when no
/// channel exceeds 255 the values are taken as 8-bit, otherwise the high byte is kept.
fn colors_to_8_bit(raw: &[[u16; 3]]) -> Option<Vec<[u8; 3]>> {
    let shift = color_shift(raw.iter().flatten().copied().max()?)?;
    Some(raw.iter().map(|rgb| rgb.map(|channel| (channel >> shift) as u8)).collect())
}

/// The shift that brings the file's colours to 8 bits, from its largest channel value;
/// `None` when every colour is black (the fields are reserved but unfilled).
pub(super) fn color_shift(max: u16) -> Option<u32> {
    (max > 0).then_some(if max <= 255 { 0 } else { 8 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_bit_colours_in_sixteen_bit_fields_are_kept() {
        assert_eq!(colors_to_8_bit(&[[255, 10, 0]]), Some(vec![[255, 10, 0]]));
    }

    #[test]
    fn sixteen_bit_colours_keep_their_high_byte() {
        assert_eq!(colors_to_8_bit(&[[65535, 256, 0]]), Some(vec![[255, 1, 0]]));
    }

    #[test]
    fn all_black_colours_are_absent() {
        assert_eq!(colors_to_8_bit(&[[0, 0, 0]]), None);
    }
}
