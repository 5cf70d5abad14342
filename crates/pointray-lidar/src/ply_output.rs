//! The points file of a scan: binary little-endian PLY with one vertex per return,
//!
//! ```text
//! double x, double y, double z, float intensity, ushort ring, float azimuth (radians),
//! float time (seconds), uchar classification, double sensor_x, double sensor_y, double sensor_z
//! ```
//!
//! 63 bytes a vertex, packed. Written here rather than through `pointray-io`'s general PLY
//! writer because this layout is fixed: positions stay double whatever their size, and every
//! field is always present.

use std::io::{self, Write};
use std::path::Path;

use pointray_io::{IoError, write_atomically};

use crate::Return;

const PROPERTIES: [(&str, &str); 11] = [
    ("double", "x"),
    ("double", "y"),
    ("double", "z"),
    ("float", "intensity"),
    ("ushort", "ring"),
    ("float", "azimuth"),
    ("float", "time"),
    ("uchar", "classification"),
    ("double", "sensor_x"),
    ("double", "sensor_y"),
    ("double", "sensor_z"),
];

/// Bytes per vertex.
pub const RECORD_BYTES: usize = 63;

/// Writes `returns` to `path` atomically; each of `comments` becomes a header comment line.
pub fn write_returns(path: &Path, returns: &[Return], comments: &[String]) -> Result<(), IoError> {
    if let Some(index) = returns.iter().position(|r| !(r.position.is_finite() && r.sensor.is_finite())) {
        return Err(IoError::unwritable(path, format!("return {index} has a non-finite coordinate")));
    }
    write_atomically(path, |out| {
        out.write_all(header(returns.len(), comments).as_bytes())?;
        returns.iter().try_for_each(|r| write_record(out, r))
    })
}

fn header(count: usize, comments: &[String]) -> String {
    let mut text = String::from("ply\nformat binary_little_endian 1.0\n");
    for comment in comments {
        // A line break would end the comment and corrupt the header.
        text += &format!("comment {}\n", comment.replace(['\n', '\r'], " "));
    }
    text += &format!("element vertex {count}\n");
    for (kind, name) in PROPERTIES {
        text += &format!("property {kind} {name}\n");
    }
    text + "end_header\n"
}

fn write_record(out: &mut impl Write, r: &Return) -> io::Result<()> {
    let mut record = [0u8; RECORD_BYTES];
    let mut at = 0;
    let mut put = |bytes: &[u8]| {
        record[at..at + bytes.len()].copy_from_slice(bytes);
        at += bytes.len();
    };
    r.position.to_array().iter().for_each(|v| put(&v.to_le_bytes()));
    put(&r.intensity.to_le_bytes());
    put(&r.ring.to_le_bytes());
    put(&r.azimuth.to_le_bytes());
    put(&r.time.to_le_bytes());
    put(&[r.classification.0]);
    r.sensor.to_array().iter().for_each(|v| put(&v.to_le_bytes()));
    out.write_all(&record)
}
