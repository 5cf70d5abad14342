//! Reading a PLY file's elements through ply-rs-bw, with the checks it does not make itself:
//! an empty or non-PLY file, a name declared twice, a body too short for the header's counts,
//! an ascii line with more or fewer values than its element's properties, bytes left over
//! after the last element, and elements that would loop forever without consuming input.

use std::collections::HashSet;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek};
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyAccess, PropertyType, ScalarType};

use super::face::{FaceRecord, index_property_name};
use super::vertex::{VertexLayout, VertexRecord};
use crate::IoError;
use crate::formats::in_plain_words;

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
    let CheckedHeader { header, layout, mut reader, .. } = read_checked_header(path)?;
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

/// A header that passed every check, with the reader at the first byte of the body.
pub(super) struct CheckedHeader {
    pub header: Header,
    pub layout: VertexLayout,
    pub reader: FileReader,
    /// Where the body starts.
    pub body_start: u64,
    /// How many bytes follow the header.
    pub body_length: u64,
}

/// Reads and checks the header; for a binary file, also that the body is long enough.
pub(super) fn read_checked_header(path: &Path) -> Result<CheckedHeader, IoError> {
    let malformed = |problem: String| IoError::malformed(path, problem);
    let mut reader = open_checked(path)?;
    let header = Parser::<VertexRecord>::new()
        .read_header(&mut reader)
        .map_err(|e| malformed(format!("bad PLY header: {}", one_line(&e.to_string()))))?;
    let body_start = reader.get_mut().stream_position().map_err(|e| IoError::os(path, e))?;
    check_unique_names(&header_text(path, body_start).map_err(|e| IoError::os(path, e))?)
        .map_err(malformed)?;
    let vertex_element =
        header.elements.get("vertex").ok_or_else(|| malformed("no 'vertex' element".into()))?;
    let layout = VertexLayout::from_element(vertex_element).map_err(malformed)?;
    check_elements(&header).map_err(malformed)?;
    let body_length = remaining_bytes(&mut reader).map_err(|e| IoError::os(path, e))?;
    if header.encoding != Encoding::Ascii {
        check_body_length(&header, body_length).map_err(malformed)?;
    }
    Ok(CheckedHeader { header, layout, reader, body_start, body_length })
}

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

/// The parser's message (which spans several lines) on one line and in words: without the
/// text it quotes (`String: '...'`, `Value: '...'`), since a file named by mistake must not
/// have its contents printed, nor the Rust error it formats for debugging
/// (`ParseIntError { kind: PosOverflow }`).
fn one_line(message: &str) -> String {
    if message.contains("Value: '") {
        return "a value is not a number, or does not fit its property's type".into();
    }
    let message = in_plain_words(message.split("String: ").next().unwrap_or_default());
    message.split(['\n', '\t']).map(str::trim).filter(|part| !part.is_empty()).collect::<Vec<_>>().join("; ")
}

/// The header as written: ply-rs-bw keeps only the last of two equal names.
fn header_text(path: &Path, length: u64) -> std::io::Result<String> {
    let mut bytes = Vec::new();
    File::open(path)?.take(length).read_to_end(&mut bytes)?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// ply-rs-bw stores elements and properties by name, so a name declared twice replaces the
/// first while the body still holds both: every value after it would land in the wrong
/// property. Refused here, before it can shift a column.
///
/// Names are kept in hash sets, so that a header of 100k properties is checked in
/// milliseconds, not the seconds a search of every earlier name per name took.
fn check_unique_names(header: &str) -> Result<(), String> {
    let (mut elements, mut properties) = (HashSet::new(), HashSet::new());
    let mut element = "(none)";
    for line in header.lines() {
        match line.split_whitespace().collect::<Vec<_>>()[..] {
            ["element", name, ..] if !elements.insert(name) => {
                return Err(format!("the header declares element '{name}' twice"));
            }
            ["element", name, ..] => {
                element = name;
                properties.clear();
            }
            ["property", .., name] if !properties.insert(name) => {
                return Err(format!(
                    "element '{element}' declares property '{name}' twice, so its values cannot be \
                     told apart"
                ));
            }
            _ => {}
        }
    }
    Ok(())
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
pub(super) fn minimum_size(property: &PropertyType) -> u64 {
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
    if header.encoding == Encoding::Ascii {
        return read_ascii_element(reader, element);
    }
    Parser::<E>::new()
        .read_payload_for_element(reader, element, header)
        .map_err(|e| format!("element '{}': {}", element.name, one_line(&e.to_string())))
}

/// Reads ascii lines one entry each, as ply-rs-bw would, but refuses a line whose count of
/// values does not match the properties: ply-rs-bw ignores extra values.
fn read_ascii_element<E: PropertyAccess>(
    reader: &mut FileReader,
    element: &ElementDef,
) -> Result<Vec<E>, String> {
    let parser = Parser::<E>::new();
    let name = &element.name;
    // The count comes from the header: reserve only what a modest file could hold.
    let mut entries = Vec::with_capacity(element.count.min(1 << 16));
    let mut line = String::new();
    for index in 0..element.count {
        line.clear();
        if reader.get_mut().read_line(&mut line).map_err(|e| e.to_string())? == 0 {
            return Err(format!(
                "element '{name}': the file ends after {index} of the {} entries the header declares",
                element.count
            ));
        }
        check_value_count(&line, element)
            .map_err(|problem| format!("element '{name}' entry {index}: {problem}"))?;
        let entry = parser
            .read_ascii_element(&line, element)
            .map_err(|e| format!("element '{name}' entry {index}: {}", one_line(&e.to_string())))?;
        entries.push(entry);
    }
    Ok(entries)
}

/// Scalars take one value each, lists their count and then that many values.
fn check_value_count(line: &str, element: &ElementDef) -> Result<(), String> {
    let values: Vec<&str> = line.split_whitespace().collect();
    let mut expected = 0;
    for (property, definition) in &element.properties {
        let taken = match definition.data_type {
            PropertyType::Scalar(_) => 1,
            PropertyType::List(..) => {
                let count = values.get(expected).and_then(|count| count.parse::<usize>().ok());
                1 + count.ok_or_else(|| format!("list '{property}' has no count"))?
            }
        };
        expected += taken;
    }
    if values.len() == expected {
        Ok(())
    } else {
        Err(format!("{} values, but its properties take {expected}", values.len()))
    }
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
