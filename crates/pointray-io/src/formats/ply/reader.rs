//! Reading a PLY file's elements through ply-rs-bw, with the checks it does not make itself:
//! an empty or non-PLY file, a body too short for the header's counts, bytes left over after
//! the last element, and elements that would loop forever without consuming input.

use std::fs::File;
use std::io::{BufRead, BufReader, Seek};
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyAccess, PropertyType, ScalarType};

use super::face::{FaceRecord, index_property_name};
use super::vertex::{VertexLayout, VertexRecord};
use crate::IoError;

/// What pointray takes from a PLY file: the vertices and, for meshes, the faces.
pub(super) struct PlyContents {
    pub layout: VertexLayout,
    pub vertices: Vec<VertexRecord>,
    /// `None` when the file has no face element or faces were not asked for.
    pub faces: Option<Vec<FaceRecord>>,
}

/// Whether a file starting with `start` is PLY ("ply" alone on the first line).
pub fn has_magic(start: &[u8]) -> bool {
    start.starts_with(b"ply\n") || start.starts_with(b"ply\r\n")
}

/// Reads the vertex element and, when `want_faces`, the face element; other elements are
/// parsed (to stay in step with the body) and dropped.
pub(super) fn read_contents(path: &Path, want_faces: bool) -> Result<PlyContents, IoError> {
    let malformed = |problem: String| IoError::malformed(path, problem);
    let mut reader = open_checked(path)?;
    let header = Parser::<VertexRecord>::new()
        .read_header(&mut reader)
        .map_err(|e| malformed(format!("bad PLY header: {}", one_line(&e.to_string()))))?;
    let vertex_element =
        header.elements.get("vertex").ok_or_else(|| malformed("no 'vertex' element".into()))?;
    let layout = VertexLayout::from_element(vertex_element).map_err(malformed)?;
    check_elements(&header).map_err(malformed)?;
    if header.encoding != Encoding::Ascii {
        let body_length = remaining_bytes(&mut reader).map_err(|e| IoError::os(path, e))?;
        check_body_length(&header, body_length).map_err(malformed)?;
    }
    let mut contents = PlyContents { layout, vertices: Vec::new(), faces: None };
    for (name, element) in &header.elements {
        match name.as_str() {
            "vertex" => contents.vertices = read_element(&mut reader, element, &header).map_err(malformed)?,
            "face" if want_faces => {
                index_property_name(element).map_err(malformed)?;
                contents.faces = Some(read_element(&mut reader, element, &header).map_err(malformed)?);
            }
            _ => {
                read_element::<SkippedElement>(&mut reader, element, &header).map_err(malformed)?;
            }
        }
    }
    check_nothing_after(&mut reader, header.encoding).map_err(malformed)?;
    Ok(contents)
}

type FileReader = Reader<BufReader<File>>;

/// Opens the file and makes sure it is a non-empty PLY file before ply-rs-bw sees it.
fn open_checked(path: &Path) -> Result<FileReader, IoError> {
    let file = File::open(path).map_err(|e| IoError::os(path, e))?;
    let mut buffered = BufReader::new(file);
    let start = buffered.fill_buf().map_err(|e| IoError::os(path, e))?;
    if start.is_empty() {
        return Err(IoError::malformed(path, "empty file"));
    }
    if !has_magic(start) {
        return Err(IoError::malformed(path, "not a PLY file (its first line is not 'ply')"));
    }
    Ok(Reader::new(buffered))
}

/// ply-rs-bw messages span several lines; ours stay on one.
/// The parser's message on one line, without the text it quotes (`String: '...'`): a file named
/// by mistake must not have its contents printed.
fn one_line(message: &str) -> String {
    let message = message.split("String: ").next().unwrap_or_default();
    message.split(['\n', '\t']).map(str::trim).filter(|part| !part.is_empty()).collect::<Vec<_>>().join("; ")
}

/// An element without properties takes no bytes, so a binary reader would spin through its
/// (possibly enormous) count without ever reaching the end of the file.
fn check_elements(header: &Header) -> Result<(), String> {
    match header.elements.values().find(|e| e.count > 0 && e.properties.is_empty()) {
        Some(element) => {
            Err(format!("element '{}' has {} entries but no properties", element.name, element.count))
        }
        None => Ok(()),
    }
}

fn remaining_bytes(reader: &mut FileReader) -> std::io::Result<u64> {
    let buffered = reader.get_mut();
    let position = buffered.stream_position()?;
    let length = buffered.get_ref().metadata()?.len();
    Ok(length.saturating_sub(position))
}

/// Every binary element needs at least its scalars and list counts; a shorter body means a
/// truncated file or a header that overstates its counts, reported before any parsing.
fn check_body_length(header: &Header, body_length: u64) -> Result<(), String> {
    let mut needed: u64 = 0;
    for element in header.elements.values() {
        let per_entry: u64 = element.properties.values().map(|p| minimum_size(&p.data_type)).sum();
        needed = (element.count as u64)
            .checked_mul(per_entry)
            .and_then(|bytes| needed.checked_add(bytes))
            .ok_or_else(|| {
                format!("the header's count for element '{}' is impossibly large", element.name)
            })?;
    }
    if needed > body_length {
        return Err(format!(
            "truncated body or a header that overstates its counts: the elements need at least \
             {needed} bytes but only {body_length} follow the header"
        ));
    }
    Ok(())
}

/// Bytes per value; a list is at least its count.
fn minimum_size(property: &PropertyType) -> u64 {
    let scalar = match property {
        PropertyType::Scalar(scalar) | PropertyType::List(scalar, _) => scalar,
    };
    match scalar {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

fn read_element<E: PropertyAccess>(
    reader: &mut FileReader,
    element: &ElementDef,
    header: &Header,
) -> Result<Vec<E>, String> {
    Parser::<E>::new()
        .read_payload_for_element(reader, element, header)
        .map_err(|e| format!("element '{}': {}", element.name, one_line(&e.to_string())))
}

/// Leftover bytes mean the header understates its counts (ascii files may end in blank lines).
/// The rest is scanned in buffer-sized chunks, never loaded whole.
fn check_nothing_after(reader: &mut FileReader, encoding: Encoding) -> Result<(), String> {
    let buffered = reader.get_mut();
    let (mut leftover, mut unexpected) = (0u64, false);
    loop {
        let chunk = buffered.fill_buf().map_err(|e| e.to_string())?;
        if chunk.is_empty() {
            break;
        }
        unexpected |= encoding != Encoding::Ascii || chunk.iter().any(|b| !b.is_ascii_whitespace());
        let length = chunk.len();
        leftover += length as u64;
        buffered.consume(length);
    }
    if unexpected {
        return Err(format!(
            "{leftover} bytes follow the last element: the header's counts do not match the body"
        ));
    }
    Ok(())
}

/// An element pointray does not use; it is parsed only to step over it.
struct SkippedElement;

impl PropertyAccess for SkippedElement {
    fn new() -> Self {
        Self
    }
}
