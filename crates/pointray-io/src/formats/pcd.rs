//! PCD (Point Cloud Library) files, read with the `pcd-rs` crate: ascii, binary and
//! binary_compressed data.
//!
//! The header is checked against the data before `pcd-rs` sees it, so that a header that
//! lies about its point count or sizes gives an error instead of a huge allocation, and a
//! header that says `DATA binary` over a text body (or over more data than its points fill)
//! gives an error instead of garbage.

use std::io::Cursor;
use std::path::Path;

use glam::{DVec3, Vec3};
use pcd_rs::{DataKind, DynReader, Field, PcdMeta, ValueKind, ViewPoint};

use super::in_plain_words;
use super::intensity::normalise_intensities;
use crate::{IoError, PointCloud};

const SUPPORTED: &str = "PCD 0.5-0.7 with DATA ascii, binary or binary_compressed; field types I/U of \
     1, 2, 4 or 8 bytes and F of 4 or 8 bytes; x y z of COUNT 1; colour as packed rgb/rgba (F 4 or U 4) \
     or r g b (U 1); ring of an integer type (I or U)";

/// A record larger than this is not a point; refusing it bounds every allocation.
const MAX_RECORD_BYTES: u64 = 1 << 20;

/// LZF turns at most 3 input bytes into 264 output bytes; anything claiming more is corrupt.
const MAX_LZF_EXPANSION: u64 = 100;

/// Reads a `.pcd` file. Points whose coordinates are NaN (PCL's marker for "no return" in
/// organised clouds) are dropped. Intensities are normalised to [0, 1]. A `ring` field gives
/// each point's scan line. A `VIEWPOINT` other than PCL's default (which every writer puts
/// there, sensor or not) gives the sensor position: its translation, in the cloud's frame.
pub fn read_pcd(path: &Path) -> Result<PointCloud, IoError> {
    let bytes = std::fs::read(path).map_err(|source| IoError::os(path, source))?;
    read_pcd_from(&bytes, path)
}

/// Reads PCD data held in memory; `origin` names it in errors.
pub fn read_pcd_from(bytes: &[u8], origin: &Path) -> Result<PointCloud, IoError> {
    if bytes.is_empty() {
        return Err(IoError::malformed(origin, "file is empty"));
    }
    let mut cursor = Cursor::new(bytes);
    let meta = PcdMeta::from_reader(&mut cursor).map_err(|error| pcd_error(origin, error))?;
    let payload = &bytes[cursor.position() as usize..];
    let layout = PcdLayout::from_meta(&meta, origin)?;
    check_payload(&meta, &layout, payload, origin)?;
    let reader = DynReader::from_bytes(bytes).map_err(|error| pcd_error(origin, error))?;
    let mut columns = PcdColumns::with_capacity(meta.num_points.min(payload.len() as u64) as usize);
    for (index, record) in reader.enumerate() {
        let record = record.map_err(|error| pcd_error(origin, error))?;
        columns
            .push(&layout, &record.0)
            .map_err(|problem| IoError::malformed(origin, format!("point {index}: {problem}")))?;
    }
    let sensor_position = (meta.viewpoint != ViewPoint::default()).then(|| {
        let ViewPoint { tx, ty, tz, .. } = meta.viewpoint;
        DVec3::new(tx, ty, tz)
    });
    Ok(PointCloud { sensor_position, ..columns.into_point_cloud(&layout) })
}

/// Sorts `pcd-rs` errors into "we cannot read this variant" and "this file is broken".
fn pcd_error(origin: &Path, error: pcd_rs::Error) -> IoError {
    match error {
        pcd_rs::Error::ParseError { desc, .. }
            if desc.contains("not supported") || desc.contains("Unsupported") =>
        {
            IoError::Unsupported { path: origin.into(), what: desc, supported: SUPPORTED.into() }
        }
        other => IoError::malformed(
            origin,
            format!("not a readable PCD file: {}", in_plain_words(&other.to_string())),
        ),
    }
}

fn unsupported(origin: &Path, what: String) -> IoError {
    IoError::Unsupported { path: origin.into(), what, supported: SUPPORTED.into() }
}

/// How a colour is stored.
#[derive(Clone, Copy)]
enum ColorFields {
    /// One packed 0x00RRGGBB value (PCL stores it in a float's bits, or as u32).
    Packed(usize),
    /// Three u8 fields.
    Separate([usize; 3]),
}

/// Where each attribute sits among a record's non-padding fields, and the record size.
struct PcdLayout {
    position: [usize; 3],
    color: Option<ColorFields>,
    intensity: Option<usize>,
    normal: Option<[usize; 3]>,
    ring: Option<usize>,
    record_bytes: u64,
}

impl PcdLayout {
    fn from_meta(meta: &PcdMeta, origin: &Path) -> Result<Self, IoError> {
        let fields: Vec<&pcd_rs::FieldDef> =
            meta.field_defs.iter().filter(|field| !field.is_padding()).collect();
        let position_of = |name: &str| fields.iter().position(|field| field.name.eq_ignore_ascii_case(name));
        // An attribute of several values a point (PCL's arrays and descriptors) is left out:
        // pointray reads one value a point.
        let find = |name: &str| {
            position_of(name).filter(|&index| match fields[index].count {
                1 => true,
                count => {
                    tracing::warn!(
                        "{}: PCD field {name} has COUNT {count}; it is left out",
                        origin.display()
                    );
                    false
                }
            })
        };
        let require = |name: &str| match position_of(name).map(|index| (index, fields[index].count)) {
            Some((index, 1)) => Ok(index),
            Some((_, count)) => Err(unsupported(origin, format!("PCD field {name} with COUNT {count}"))),
            None => Err(IoError::malformed(origin, format!("PCD has no field {name:?}"))),
        };
        let position = [require("x")?, require("y")?, require("z")?];
        let group = |names: [&str; 3]| match (find(names[0]), find(names[1]), find(names[2])) {
            (Some(a), Some(b), Some(c)) => Some([a, b, c]),
            _ => None,
        };
        let color =
            Self::color_fields(&fields, find("rgb").or(find("rgba")), group(["r", "g", "b"]), origin)?;
        let normal = group(["normal_x", "normal_y", "normal_z"]);
        let intensity = find("intensity");
        let ring = find("ring");
        if let Some(index) = ring
            && matches!(fields[index].kind, ValueKind::F32 | ValueKind::F64)
        {
            return Err(unsupported(origin, format!("PCD ring field of type {:?}", fields[index].kind)));
        }
        Ok(Self { position, color, intensity, normal, ring, record_bytes: record_bytes(meta, origin)? })
    }

    fn color_fields(
        fields: &[&pcd_rs::FieldDef],
        packed: Option<usize>,
        separate: Option<[usize; 3]>,
        origin: &Path,
    ) -> Result<Option<ColorFields>, IoError> {
        if let Some(index) = packed {
            return match fields[index].kind {
                ValueKind::F32 | ValueKind::U32 => Ok(Some(ColorFields::Packed(index))),
                kind => Err(unsupported(origin, format!("PCD packed colour field of type {kind:?}"))),
            };
        }
        let Some(indices) = separate else { return Ok(None) };
        match indices.iter().find(|&&index| fields[index].kind != ValueKind::U8) {
            Some(&index) => {
                Err(unsupported(origin, format!("PCD colour field of type {:?}", fields[index].kind)))
            }
            None => Ok(Some(ColorFields::Separate(indices))),
        }
    }
}

/// Bytes per binary record (padding included), refusing absurd sizes before any arithmetic
/// can overflow.
fn record_bytes(meta: &PcdMeta, origin: &Path) -> Result<u64, IoError> {
    let mut total: u64 = 0;
    for field in meta.field_defs.iter() {
        total = (field.kind.byte_size() as u64)
            .checked_mul(field.count)
            .and_then(|bytes| total.checked_add(bytes))
            .filter(|&bytes| bytes <= MAX_RECORD_BYTES)
            .ok_or_else(|| {
                IoError::malformed(origin, format!("PCD record exceeds {MAX_RECORD_BYTES} bytes"))
            })?;
    }
    Ok(total)
}

/// Makes sure the data section can hold what the header promises.
fn check_payload(meta: &PcdMeta, layout: &PcdLayout, payload: &[u8], origin: &Path) -> Result<(), IoError> {
    let needed = meta.num_points.checked_mul(layout.record_bytes);
    let truncated = |have: u64| {
        let need = needed.map_or("more than 2^64".into(), |n| n.to_string());
        let problem =
            format!("PCD declares {} points needing {need} bytes of data, found {have}", meta.num_points);
        Err(IoError::malformed(origin, problem))
    };
    match meta.data {
        DataKind::Ascii => Ok(()),
        DataKind::Binary if looks_like_text(payload) => Err(IoError::malformed(
            origin,
            "the header says DATA binary, but the data is text (numbers in lines): it should say DATA ascii",
        )),
        DataKind::Binary => match needed {
            Some(needed) if needed == payload.len() as u64 => Ok(()),
            // PCL and pypcd4 read the declared points and leave the rest, and so does pointray.
            Some(needed) if needed < payload.len() as u64 => {
                tracing::warn!(
                    "{}: {} bytes follow the {} points the header declares; they are left out",
                    origin.display(),
                    payload.len() as u64 - needed,
                    meta.num_points
                );
                Ok(())
            }
            _ => truncated(payload.len() as u64),
        },
        DataKind::BinaryCompressed => {
            let [compressed, uncompressed] = compressed_sizes(payload, origin)?;
            if compressed > payload.len() as u64 - 8 {
                return truncated(payload.len() as u64 - 8);
            }
            let plausible = uncompressed <= compressed.saturating_mul(MAX_LZF_EXPANSION);
            let empty = meta.num_points == 0 && compressed == 0 && uncompressed == 0;
            if !empty && (needed != Some(uncompressed) || !plausible) {
                let problem = format!(
                    "PCD compressed block claims {uncompressed} bytes from {compressed}, \
                     but {} points need {}",
                    meta.num_points,
                    needed.unwrap_or(u64::MAX)
                );
                return Err(IoError::malformed(origin, problem));
            }
            Ok(())
        }
    }
}

/// Whether binary data is in fact lines of numbers: every byte printable or a line break,
/// and the first line at least three numbers. Binary floats and integers hold control bytes
/// almost at once.
fn looks_like_text(payload: &[u8]) -> bool {
    let head = &payload[..payload.len().min(4096)];
    let printable = head.iter().all(|&byte| byte.is_ascii_graphic() || byte.is_ascii_whitespace());
    let first_line = head.split(|&byte| byte == b'\n').next().unwrap_or_default();
    let numbers = String::from_utf8_lossy(first_line)
        .split_whitespace()
        .map(|token| token.parse::<f64>().is_ok())
        .collect::<Vec<_>>();
    printable && !head.is_empty() && numbers.iter().all(|&number| number) && numbers.len() >= 3
}

fn compressed_sizes(payload: &[u8], origin: &Path) -> Result<[u64; 2], IoError> {
    let word = |at: usize| -> Option<u64> {
        Some(u32::from_le_bytes(payload.get(at..at + 4)?.try_into().ok()?).into())
    };
    match (word(0), word(4)) {
        (Some(compressed), Some(uncompressed)) => Ok([compressed, uncompressed]),
        _ => Err(IoError::malformed(origin, "PCD binary_compressed data lacks its size header")),
    }
}

/// The single value of a COUNT-1 field, as f64.
fn scalar(field: &Field) -> f64 {
    fn first<T: Copy + Into<f64>>(values: &[T]) -> f64 {
        values.first().map_or(f64::NAN, |&value| value.into())
    }
    match field {
        Field::I8(v) => first(v),
        Field::I16(v) => first(v),
        Field::I32(v) => first(v),
        Field::I64(v) => v.first().map_or(f64::NAN, |&value| value as f64),
        Field::U8(v) => first(v),
        Field::U16(v) => first(v),
        Field::U32(v) => first(v),
        Field::U64(v) => v.first().map_or(f64::NAN, |&value| value as f64),
        Field::F32(v) => first(v),
        Field::F64(v) => first(v),
    }
}

fn packed_color(field: &Field) -> [u8; 3] {
    let bits = match field {
        Field::F32(values) => values.first().map_or(0, |value| value.to_bits()),
        Field::U32(values) => values.first().copied().unwrap_or(0),
        _ => 0,
    };
    [(bits >> 16) as u8, (bits >> 8) as u8, bits as u8]
}

#[derive(Default)]
struct PcdColumns {
    positions: Vec<DVec3>,
    colors: Vec<[u8; 3]>,
    intensities: Vec<f64>,
    normals: Vec<Vec3>,
    rings: Vec<u16>,
}

impl PcdColumns {
    fn with_capacity(points: usize) -> Self {
        Self { positions: Vec::with_capacity(points), ..Self::default() }
    }

    /// Adds a record's point; a point without a position (NaN) is skipped, a ring out of
    /// range is an error.
    fn push(&mut self, layout: &PcdLayout, fields: &[Field]) -> Result<(), String> {
        let [x, y, z] = layout.position.map(|index| scalar(&fields[index]));
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            return Ok(());
        }
        if let Some(index) = layout.ring {
            let ring = scalar(&fields[index]);
            if !(0.0..=f64::from(u16::MAX)).contains(&ring) {
                return Err(format!("ring {ring} is outside 0 to {}", u16::MAX));
            }
            self.rings.push(ring as u16);
        }
        self.positions.push(DVec3::new(x, y, z));
        match layout.color {
            Some(ColorFields::Packed(index)) => self.colors.push(packed_color(&fields[index])),
            Some(ColorFields::Separate(indices)) => {
                self.colors.push(indices.map(|i| scalar(&fields[i]) as u8))
            }
            None => {}
        }
        self.intensities.extend(layout.intensity.map(|index| scalar(&fields[index])));
        if let Some(indices) = layout.normal {
            let [nx, ny, nz] = indices.map(|index| scalar(&fields[index]) as f32);
            self.normals.push(Vec3::new(nx, ny, nz));
        }
        Ok(())
    }

    fn into_point_cloud(self, layout: &PcdLayout) -> PointCloud {
        PointCloud {
            colors: layout.color.is_some().then_some(self.colors),
            intensities: normalise_intensities(&self.intensities),
            normals: layout.normal.is_some().then_some(self.normals),
            rings: layout.ring.is_some().then_some(self.rings),
            ..PointCloud::from_positions(self.positions)
        }
    }
}
