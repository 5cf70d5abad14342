//! The parts `sample --tile I --of N` writes, joined in order into one points file without
//! holding them in memory: binary PLY bodies of one vertex layout follow each other as they are.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};

use pointray_io::IoError;

/// A header longer than this is no part `sample` wrote.
const LONGEST_HEADER: u64 = 4096;

/// One part: where its vertex records start, how many there are, and their layout (the
/// header's `property` lines).
struct Part {
    path: PathBuf,
    body_start: u64,
    vertices: u64,
    properties: Vec<String>,
}

/// Writes `parts`, in the order given, as one binary PLY `output` (atomically); returns the
/// points written. Every part is checked whole before anything is written.
pub fn join_parts(parts: &[PathBuf], output: &Path) -> Result<u64, IoError> {
    let parts = parts.iter().map(|path| read_part(path)).collect::<Result<Vec<_>, _>>()?;
    let Some(first) = parts.first() else {
        return Err(IoError::unwritable(output, "no parts to join"));
    };
    if let Some(other) = parts.iter().find(|part| part.properties != first.properties) {
        let problem = format!(
            "its vertices are laid out as {:?}, not as {:?} of {}",
            other.properties,
            first.properties,
            first.path.display()
        );
        return Err(IoError::malformed(&other.path, problem));
    }
    let vertices: u64 = parts.iter().map(|part| part.vertices).sum();
    pointray_io::write_atomically(output, |out| {
        write!(
            out,
            "ply\nformat binary_little_endian 1.0\ncomment written by pointray\nelement vertex {vertices}\n"
        )?;
        first.properties.iter().try_for_each(|line| writeln!(out, "{line}"))?;
        out.write_all(b"end_header\n")?;
        for part in &parts {
            let mut body = BufReader::new(File::open(&part.path)?);
            body.seek_relative(part.body_start as i64)?;
            std::io::copy(&mut body, out)?;
        }
        Ok(())
    })?;
    Ok(vertices)
}

/// The header of a part `sample` wrote (binary little-endian, one `vertex` element of scalar
/// properties), checked against the file's length.
fn read_part(path: &Path) -> Result<Part, IoError> {
    let not_a_part =
        |problem: &str| IoError::malformed(path, format!("not a part `pointray sample` wrote: {problem}"));
    let file = File::open(path).map_err(|e| IoError::os(path, e))?;
    let length = file.metadata().map_err(|e| IoError::os(path, e))?.len();
    let header = header_text(file).map_err(|e| IoError::os(path, e))?;
    let header = header.ok_or_else(|| not_a_part("no PLY header that ends within 4 KiB"))?;
    let mut lines = header.lines().filter(|line| !line.starts_with("comment "));
    if lines.next() != Some("ply") || lines.next() != Some("format binary_little_endian 1.0") {
        return Err(not_a_part("no binary little-endian PLY header"));
    }
    let vertices = lines
        .next()
        .and_then(|line| line.strip_prefix("element vertex "))
        .and_then(|count| count.parse::<u64>().ok())
        .ok_or_else(|| not_a_part("its first element is not `vertex`"))?;
    let properties: Vec<String> =
        lines.take_while(|line| *line != "end_header").map(str::to_string).collect();
    let record_bytes = properties.iter().map(|line| scalar_bytes(line)).sum::<Option<u64>>();
    let record_bytes =
        record_bytes.ok_or_else(|| not_a_part("a header line other than a scalar property"))?;
    let body_start = header.len() as u64;
    if vertices.checked_mul(record_bytes).and_then(|body| body.checked_add(body_start)) != Some(length) {
        return Err(not_a_part(&format!("its {length} bytes do not hold its {vertices} vertices")));
    }
    Ok(Part { path: path.to_path_buf(), body_start, vertices, properties })
}

/// The file's header, up to and with its `end_header` line; `None` when none ends within
/// `LONGEST_HEADER` bytes or it is not text.
fn header_text(file: File) -> std::io::Result<Option<String>> {
    let mut reader = BufReader::new(file.take(LONGEST_HEADER));
    let mut header = Vec::new();
    while !header.ends_with(b"end_header\n") {
        if reader.read_until(b'\n', &mut header)? == 0 {
            return Ok(None);
        }
    }
    Ok(String::from_utf8(header).ok())
}

/// The bytes of a `property TYPE NAME` line's scalar.
fn scalar_bytes(line: &str) -> Option<u64> {
    match line.split_whitespace().collect::<Vec<_>>()[..] {
        ["property", "char" | "uchar" | "int8" | "uint8", _] => Some(1),
        ["property", "short" | "ushort" | "int16" | "uint16", _] => Some(2),
        ["property", "int" | "uint" | "float" | "int32" | "uint32" | "float32", _] => Some(4),
        ["property", "double" | "float64", _] => Some(8),
        _ => None,
    }
}
