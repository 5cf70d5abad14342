//! Text point clouds: `.xyz`, `.pts`, `.txt`, `.csv`.
//!
//! One point per line, values separated by whitespace, commas or semicolons: one of these
//! throughout the file. Which column holds what comes from, in order: the caller's
//! [`ColumnSpec`]; a header line of names (CSV style) as the first content line; otherwise
//! the number of values on the first point line (see [`ColumnSpec::for_column_count`]).
//! Every point line must have as many values as the layout. Lines starting with `#` or `//`
//! are comments. A line holding a single integer is a point-count line (PTS writes one
//! before each scan) and is skipped.

use std::path::Path;

use super::column_rows::ColumnRows;
use super::columns::ColumnSpec;
use crate::{IoError, PointCloud};

/// Reads a text point file. Colours are 8-bit (0-255); files whose colours are all in
/// [0, 1] are taken as float colours and scaled, and 16-bit colours (up to 65535) are
/// scaled down. Intensities are normalised to [0, 1].
pub fn read_xyz(path: &Path, spec: Option<&ColumnSpec>) -> Result<PointCloud, IoError> {
    let bytes = std::fs::read(path).map_err(|source| IoError::os(path, source))?;
    read_xyz_from(&bytes, path, spec)
}

/// Reads text point data held in memory; `origin` names it in errors.
pub fn read_xyz_from(bytes: &[u8], origin: &Path, spec: Option<&ColumnSpec>) -> Result<PointCloud, IoError> {
    let malformed = |problem| IoError::malformed(origin, problem);
    let text = std::str::from_utf8(bytes).map_err(|error| malformed(format!("not UTF-8 text: {error}")))?;
    let mut table = TextTable { spec: spec.cloned(), header_seen: false, rows: None, separator: None };
    for (index, line) in text.lines().enumerate() {
        table.add_line(line, index + 1).map_err(malformed)?;
    }
    match table.rows {
        Some(rows) => rows.into_point_cloud().map_err(malformed),
        None => Err(malformed("no point lines found (expected x y z per line)".into())),
    }
}

/// How a line separates its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Separator {
    Whitespace,
    Comma,
    Semicolon,
}

impl Separator {
    fn describe(self) -> &'static str {
        match self {
            Self::Whitespace => "whitespace",
            Self::Comma => "commas",
            Self::Semicolon => "semicolons",
        }
    }
}

/// A line's fields and its separator. Spaces may pad comma- or semicolon-separated values,
/// but not separate them too ("1,2 3"), and a value may be missing only at the end ("1,2,3,").
fn split_line(line: &str) -> Result<(Separator, Vec<&str>), String> {
    let (separator, delimiter) = match (line.contains(','), line.contains(';')) {
        (false, false) => return Ok((Separator::Whitespace, line.split_whitespace().collect())),
        (true, false) => (Separator::Comma, ','),
        (false, true) => (Separator::Semicolon, ';'),
        (true, true) => return Err("mixes commas and semicolons".into()),
    };
    let mut fields: Vec<&str> = line.split(delimiter).map(str::trim).collect();
    if fields.last() == Some(&"") {
        fields.pop();
    }
    if fields.iter().any(|field| field.is_empty()) {
        return Err(format!("has an empty value between {}", separator.describe()));
    }
    if fields.iter().any(|field| field.contains(char::is_whitespace)) {
        return Err(format!("mixes {} and whitespace between values", separator.describe()));
    }
    Ok((separator, fields))
}

/// The layout once known, the values read so far, and the separator of the point lines.
struct TextTable {
    spec: Option<ColumnSpec>,
    header_seen: bool,
    rows: Option<ColumnRows>,
    separator: Option<(Separator, usize)>,
}

impl TextTable {
    fn add_line(&mut self, line: &str, number: usize) -> Result<(), String> {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') || trimmed.starts_with("//") {
            return Ok(());
        }
        let (separator, fields) =
            split_line(trimmed).map_err(|problem| format!("line {number} {problem}"))?;
        if fields.len() == 1 && fields[0].parse::<u64>().is_ok() {
            return Ok(()); // a PTS point-count line
        }
        let values: Result<Vec<f64>, _> = fields.iter().map(|field| field.parse::<f64>()).collect();
        match values {
            Ok(values) => {
                self.check_separator(separator, number)?;
                self.rows_for(values.len(), number)?.push(&values).map_err(|problem| {
                    let layout = self.spec.as_ref().map(|spec| format!(" ({spec})")).unwrap_or_default();
                    format!("line {number}: {problem}{layout}")
                })
            }
            Err(_) if self.rows.is_none() && !self.header_seen => self.use_header(&fields, number),
            Err(error) => Err(format!("line {number}: {error}")),
        }
    }

    /// Every point line separates its values as the first one does.
    fn check_separator(&mut self, separator: Separator, number: usize) -> Result<(), String> {
        match self.separator {
            None => self.separator = Some((separator, number)),
            Some((first, first_line)) if first != separator => {
                return Err(format!(
                    "line {number} separates values by {}, line {first_line} by {}: mixed separators",
                    separator.describe(),
                    first.describe()
                ));
            }
            Some(_) => {}
        }
        Ok(())
    }

    /// The rows, started on the first point line with the layout known by then.
    fn rows_for(&mut self, count: usize, number: usize) -> Result<&mut ColumnRows, String> {
        if self.spec.is_none() {
            let spec = ColumnSpec::for_column_count(count).ok_or_else(|| {
                format!(
                    "line {number}: {count} values per line fit no layout pointray can assume \
                     (3 = x y z, 4 = x y z i, 6 = x y z r g b, 7 = x y z i r g b, \
                     9 = x y z r g b nx ny nz, 10 = x y z i r g b nx ny nz); name the columns \
                     with a header line or a column spec such as x,y,z,intensity,ring"
                )
            })?;
            self.spec = Some(spec);
        }
        let spec = self.spec.as_ref().ok_or("no layout")?;
        Ok(self.rows.get_or_insert_with(|| ColumnRows::new(spec, 0)))
    }

    /// A header line sets the layout, unless the caller gave one (theirs wins).
    fn use_header(&mut self, names: &[&str], number: usize) -> Result<(), String> {
        self.header_seen = true;
        if self.spec.is_none() {
            let spec =
                ColumnSpec::from_header(names, &format!("header on line {number}")).map_err(|error| {
                    format!("line {number} is neither numbers nor a header naming x, y and z: {error}")
                })?;
            self.spec = Some(spec);
        }
        Ok(())
    }
}
