//! Binary PLY read in chunks of vertices (`point_stream`, and whole reads, a chunk at a time
//! on every core): the vertex element's fixed-size records are decoded straight from the
//! file, with the checks and conversions of the element-by-element read. Files whose
//! vertices cannot be reached without parsing (ascii, a list property, an element before the
//! vertices) are not chunked.

use glam::DVec3;
use rayon::prelude::*;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use ply_rs_bw::ply::{Encoding, PropertyType, ScalarType};

use super::reader::{CheckedHeader, minimum_size, read_checked_header};
use super::vertex::{
    Field, VertexLayout, VertexRecord, checked_positions, intensity_divisor, into_point_cloud_from,
    largest_intensity, renumbered,
};
use crate::{AttributeBytes, IoError, PointCloud};

pub(crate) struct PlyChunks {
    path: PathBuf,
    reader: BufReader<File>,
    layout: VertexLayout,
    /// Each vertex property in file order: its type, its size in bytes and the record field
    /// it fills.
    properties: Vec<(ScalarType, usize, Option<Field>)>,
    big_endian: bool,
    record_bytes: usize,
    body_start: u64,
    count: u64,
    read: u64,
    /// Whether every element has fixed-size records, so that `open` checked the body's length
    /// against the header's counts to the byte.
    body_checked: bool,
}

/// Vertices decoded at a time when a file is read whole: enough to keep every core busy,
/// few enough that the raw bytes and decoded records of one chunk stay small beside the cloud.
const WHOLE_READ_CHUNK: usize = 1 << 20;

impl PlyChunks {
    /// `None` when the file is PLY that cannot be read in chunks.
    pub(crate) fn open(path: &Path) -> Result<Option<Self>, IoError> {
        let CheckedHeader { header, layout, reader, body_start, body_length } = read_checked_header(path)?;
        let big_endian = match header.encoding {
            Encoding::Ascii => return Ok(None),
            Encoding::BinaryBigEndian => true,
            Encoding::BinaryLittleEndian => false,
        };
        let Some((name, vertex)) = header.elements.iter().next().filter(|(name, _)| *name == "vertex") else {
            return Ok(None);
        };
        debug_assert_eq!(name, "vertex");
        let mut properties = Vec::new();
        for (name, property) in &vertex.properties {
            let PropertyType::Scalar(scalar) = &property.data_type else { return Ok(None) };
            properties.push((scalar.clone(), minimum_size(&property.data_type) as usize, Field::named(name)));
        }
        let record_bytes: u64 = vertex.properties.values().map(|p| minimum_size(&p.data_type)).sum();
        let fixed_size = header.elements.values().all(|e| e.properties.values().all(is_scalar));
        let needed: u64 = header
            .elements
            .values()
            .map(|e| e.count as u64 * e.properties.values().map(|p| minimum_size(&p.data_type)).sum::<u64>())
            .sum();
        if fixed_size && needed != body_length {
            let problem = format!(
                "{} bytes follow the last element: the header's counts do not match the body",
                body_length - needed
            );
            return Err(IoError::malformed(path, problem));
        }
        Ok(Some(Self {
            path: path.to_path_buf(),
            reader: reader.into_inner(),
            layout,
            properties,
            big_endian,
            record_bytes: record_bytes as usize,
            body_start,
            count: vertex.count as u64,
            read: 0,
            body_checked: fixed_size,
        }))
    }

    /// Every vertex, decoded a chunk at a time on every core; `None` for a file whose body
    /// `open` could not check whole (an element of lists, such as a mesh's faces), which the
    /// element-by-element read checks instead.
    pub(crate) fn read_whole(mut self) -> Result<Option<PointCloud>, IoError> {
        if !self.body_checked {
            return Ok(None);
        }
        let mut largest = 0.0;
        if self.layout.intensity_unit.is_some() {
            while self.next(WHOLE_READ_CHUNK, &mut largest, true)?.is_some() {}
            self.rewind()?;
        }
        let mut cloud = into_point_cloud_from(&[], &self.layout, 0, intensity_divisor(largest))
            .map_err(|problem| IoError::malformed(&self.path, problem))?;
        cloud.positions.reserve_exact(self.count as usize);
        while let Some(chunk) = self.next(WHOLE_READ_CHUNK, &mut largest, false)? {
            cloud.append(chunk);
        }
        Ok(Some(cloud))
    }

    pub(crate) fn declared_points(&self) -> u64 {
        self.count
    }

    /// The attributes the chunks carry.
    pub(crate) fn attributes(&self) -> AttributeBytes {
        let layout = &self.layout;
        AttributeBytes {
            normals: layout.has_normals,
            colors: layout.color_unit.is_some(),
            intensities: layout.intensity_unit.is_some(),
            classifications: layout.has_classifications,
            rings: layout.has_rings,
            sensor_origins: layout.has_sensor_origins,
        }
    }

    pub(crate) fn rewind(&mut self) -> Result<(), IoError> {
        self.reader.seek(SeekFrom::Start(self.body_start)).map_err(|e| IoError::os(&self.path, e))?;
        self.read = 0;
        Ok(())
    }

    /// Up to `max` more vertices, or `None` at the end. A survey notes the largest
    /// intensity in `largest` and returns positions only; otherwise intensities are divided
    /// as the whole file's largest says.
    pub(crate) fn next(
        &mut self,
        max: usize,
        largest: &mut f64,
        survey: bool,
    ) -> Result<Option<PointCloud>, IoError> {
        let count = (self.count - self.read).min(max.max(1) as u64) as usize;
        if count == 0 {
            return Ok(None);
        }
        let mut bytes = vec![0u8; count * self.record_bytes];
        self.reader.read_exact(&mut bytes).map_err(|e| IoError::os(&self.path, e))?;
        let first = self.read;
        self.read += count as u64;
        let unit = self.layout.intensity_unit;
        let malformed = |problem| IoError::malformed(&self.path, renumbered(problem, first));
        if (survey && unit.is_none()) || self.attributes() == AttributeBytes::default() {
            // Positions alone, without whole records that would only be dropped.
            let positions = bytes.par_chunks_exact(self.record_bytes).map(|r| self.position(r)).collect();
            return checked_positions(positions)
                .map(|p| Some(PointCloud::from_positions(p)))
                .map_err(malformed);
        }
        let records: Vec<VertexRecord> =
            bytes.par_chunks_exact(self.record_bytes).map(|r| self.record(r)).collect();
        drop(bytes);
        let mut layout = self.layout.clone();
        if survey {
            if let Some(unit) = unit {
                *largest = largest.max(largest_intensity(&records, unit));
            }
            layout = VertexLayout::positions_only();
        }
        into_point_cloud_from(&records, &layout, first, intensity_divisor(*largest))
            .map(Some)
            .map_err(|problem| IoError::malformed(&self.path, problem))
    }

    fn record(&self, bytes: &[u8]) -> VertexRecord {
        let mut record = VertexRecord::default();
        self.decode(bytes, |field, value| *record.slot(field) = value);
        record
    }

    fn position(&self, bytes: &[u8]) -> DVec3 {
        let mut position = DVec3::ZERO;
        self.decode(bytes, |field, value| {
            if let Field::Position(axis) = field {
                position[axis] = value;
            }
        });
        position
    }

    /// Hands each value of a record's `bytes` that fills a field to `set`.
    fn decode(&self, mut bytes: &[u8], mut set: impl FnMut(Field, f64)) {
        for (scalar, size, field) in &self.properties {
            let (value, rest) = bytes.split_at(*size);
            bytes = rest;
            if let Some(field) = field {
                set(*field, scalar_from(scalar, value, self.big_endian));
            }
        }
    }
}

fn is_scalar(property: &ply_rs_bw::ply::PropertyDef) -> bool {
    matches!(property.data_type, PropertyType::Scalar(_))
}

/// One stored value, widened to f64.
fn scalar_from(scalar: &ScalarType, bytes: &[u8], big_endian: bool) -> f64 {
    macro_rules! number {
        ($type:ty) => {{
            let array = bytes.try_into().expect("the slice has the type's size");
            f64::from(if big_endian { <$type>::from_be_bytes(array) } else { <$type>::from_le_bytes(array) })
        }};
    }
    match scalar {
        ScalarType::Char => number!(i8),
        ScalarType::UChar => number!(u8),
        ScalarType::Short => number!(i16),
        ScalarType::UShort => number!(u16),
        ScalarType::Int => number!(i32),
        ScalarType::UInt => number!(u32),
        ScalarType::Float => number!(f32),
        ScalarType::Double => number!(f64),
    }
}
