//! Text point clouds: `.xyz`, `.pts`, `.txt`, `.csv`.
//!
//! One point per line, values separated by whitespace, commas or semicolons. Which column
//! holds what comes from, in order: the caller's [`ColumnSpec`]; a header line of names
//! (CSV style) as the first content line; otherwise the number of columns (see
//! [`ColumnSpec::for_column_count`]). Lines starting with `#` or `//` are comments. A line
//! holding a single integer is a point-count line (PTS writes one before each scan) and is
//! skipped.

use std::path::Path;
use std::str::FromStr;

use glam::{DVec3, Vec3};

use super::intensity::normalise_intensities;
use crate::{IoError, PointCloud};

/// What one text column holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Column {
    X,
    Y,
    Z,
    Intensity,
    Red,
    Green,
    Blue,
    NormalX,
    NormalY,
    NormalZ,
    /// A column we do not use (written `_` or `skip` in a spec).
    Skip,
}

impl Column {
    /// Accepts the short spec names and the usual long header names, any case.
    fn from_name(name: &str) -> Option<Self> {
        let column = match name.trim().trim_matches('"').to_ascii_lowercase().as_str() {
            "x" | "//x" => Self::X,
            "y" => Self::Y,
            "z" => Self::Z,
            "i" | "intensity" | "scalar_intensity" | "reflectance" => Self::Intensity,
            "r" | "red" => Self::Red,
            "g" | "green" => Self::Green,
            "b" | "blue" => Self::Blue,
            "nx" | "normal_x" | "normalx" => Self::NormalX,
            "ny" | "normal_y" | "normaly" => Self::NormalY,
            "nz" | "normal_z" | "normalz" => Self::NormalZ,
            "_" | "skip" => Self::Skip,
            _ => return None,
        };
        Some(column)
    }
}

/// The meaning of each column of a text point file, e.g. `"x,y,z,i,r,g,b"`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColumnSpec {
    columns: Vec<Column>,
}

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum ColumnSpecError {
    #[error("column spec {spec:?}: unknown column name {name:?}; known: x y z i r g b nx ny nz _")]
    UnknownName { spec: String, name: String },
    #[error("column spec {spec:?}: column {column:?} appears twice")]
    Duplicate { spec: String, column: Column },
    #[error("column spec {spec:?}: needs x, y and z")]
    MissingPosition { spec: String },
    #[error("column spec {spec:?}: {group} must be given together")]
    PartialGroup { spec: String, group: &'static str },
}

impl ColumnSpec {
    /// Parses names separated by commas or whitespace. `x`, `y` and `z` are required;
    /// `r g b` and `nx ny nz` come as complete groups.
    pub fn parse(spec: &str) -> Result<Self, ColumnSpecError> {
        let columns = split_fields(spec)
            .map(|name| {
                Column::from_name(name)
                    .ok_or_else(|| ColumnSpecError::UnknownName { spec: spec.into(), name: name.into() })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::validated(columns, spec)
    }

    /// The column layout assumed when a file has neither a spec nor a header, by the
    /// number of columns of its first point line: 4 = x y z i; 6 = x y z r g b;
    /// 7 = x y z i r g b (PTS); 9 = x y z r g b nx ny nz; 10 = x y z i r g b nx ny nz;
    /// anything else = x y z with the rest ignored.
    pub fn for_column_count(count: usize) -> Self {
        use Column::*;
        let columns = match count {
            4 => vec![X, Y, Z, Intensity],
            6 => vec![X, Y, Z, Red, Green, Blue],
            7 => vec![X, Y, Z, Intensity, Red, Green, Blue],
            9 => vec![X, Y, Z, Red, Green, Blue, NormalX, NormalY, NormalZ],
            10 => vec![X, Y, Z, Intensity, Red, Green, Blue, NormalX, NormalY, NormalZ],
            _ => vec![X, Y, Z],
        };
        Self { columns }
    }

    /// A header line's names; names we do not know become skipped columns.
    fn from_header(names: &[&str], line: &str) -> Result<Self, ColumnSpecError> {
        let columns = names.iter().map(|name| Column::from_name(name).unwrap_or(Column::Skip)).collect();
        Self::validated(columns, line)
    }

    fn validated(columns: Vec<Column>, spec: &str) -> Result<Self, ColumnSpecError> {
        for (index, column) in columns.iter().enumerate() {
            if *column != Column::Skip && columns[..index].contains(column) {
                return Err(ColumnSpecError::Duplicate { spec: spec.into(), column: *column });
            }
        }
        let has = |column| columns.contains(&column);
        if !(has(Column::X) && has(Column::Y) && has(Column::Z)) {
            return Err(ColumnSpecError::MissingPosition { spec: spec.into() });
        }
        let groups = [
            ("r, g and b", [Column::Red, Column::Green, Column::Blue]),
            ("nx, ny and nz", [Column::NormalX, Column::NormalY, Column::NormalZ]),
        ];
        for (group, members) in groups {
            let present = members.iter().filter(|member| has(**member)).count();
            if present != 0 && present != members.len() {
                return Err(ColumnSpecError::PartialGroup { spec: spec.into(), group });
            }
        }
        Ok(Self { columns })
    }

    fn index_of(&self, column: Column) -> Option<usize> {
        self.columns.iter().position(|c| *c == column)
    }

    /// How many values a line must have.
    fn width(&self) -> usize {
        self.columns.len()
    }
}

impl FromStr for ColumnSpec {
    type Err = ColumnSpecError;

    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        Self::parse(spec)
    }
}

/// Reads a text point file. Colours are 8-bit (0-255); files whose colours are all in
/// [0, 1] are taken as float colours and scaled, and 16-bit colours (up to 65535) are
/// scaled down. Intensities are normalised to [0, 1].
pub fn read_xyz(path: &Path, spec: Option<&ColumnSpec>) -> Result<PointCloud, IoError> {
    let bytes = std::fs::read(path).map_err(|source| IoError::os(path, source))?;
    read_xyz_from(&bytes, path, spec)
}

/// Reads text point data held in memory; `origin` names it in errors.
pub fn read_xyz_from(bytes: &[u8], origin: &Path, spec: Option<&ColumnSpec>) -> Result<PointCloud, IoError> {
    let text = std::str::from_utf8(bytes)
        .map_err(|error| IoError::malformed(origin, format!("not UTF-8 text: {error}")))?;
    let mut table = TextTable { spec: spec.cloned(), header_seen: false, rows: Rows::default() };
    for (index, line) in text.lines().enumerate() {
        table.add_line(line, index + 1).map_err(|problem| IoError::malformed(origin, problem))?;
    }
    match table.spec {
        Some(spec) => {
            table.rows.into_point_cloud(&spec).map_err(|problem| IoError::malformed(origin, problem))
        }
        None => Err(IoError::malformed(origin, "no point lines found (expected x y z per line)")),
    }
}

fn split_fields(line: &str) -> impl Iterator<Item = &str> {
    line.split(|c: char| c == ',' || c == ';' || c.is_whitespace()).filter(|field| !field.is_empty())
}

/// The layout once known, and the values read so far.
struct TextTable {
    spec: Option<ColumnSpec>,
    header_seen: bool,
    rows: Rows,
}

impl TextTable {
    /// A header line sets the layout, unless the caller gave one (theirs wins).
    fn use_header(&mut self, names: &[&str], number: usize) -> Result<(), String> {
        self.header_seen = true;
        if self.spec.is_none() {
            // Named by its line, not quoted: a file that is no point cloud at all (a system file
            // named by mistake) must not have its contents printed.
            let spec =
                ColumnSpec::from_header(names, &format!("header on line {number}")).map_err(|error| {
                    format!("line {number} is neither numbers nor a header naming x, y and z: {error}")
                })?;
            self.spec = Some(spec);
        }
        Ok(())
    }

    fn add_line(&mut self, line: &str, number: usize) -> Result<(), String> {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') || trimmed.starts_with("//") {
            return Ok(());
        }
        let fields: Vec<&str> = split_fields(trimmed).collect();
        if fields.len() == 1 && fields[0].parse::<u64>().is_ok() {
            return Ok(()); // a PTS point-count line
        }
        let values: Result<Vec<f64>, _> = fields.iter().map(|field| field.parse::<f64>()).collect();
        match (values, &self.spec) {
            (Ok(values), Some(spec)) => self.rows.push(spec, &values, number),
            (Ok(values), None) => {
                let spec = ColumnSpec::for_column_count(values.len());
                let pushed = self.rows.push(&spec, &values, number);
                self.spec = Some(spec);
                pushed
            }
            (Err(_), _) if self.rows.is_empty() && !self.header_seen => self.use_header(&fields, number),
            (Err(error), _) => Err(format!("line {number}: {error}")),
        }
    }
}

/// Raw values, converted only at the end when the value ranges are known.
#[derive(Default)]
struct Rows {
    positions: Vec<DVec3>,
    intensities: Vec<f64>,
    colors: Vec<[f64; 3]>,
    normals: Vec<Vec3>,
}

impl Rows {
    fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    fn push(&mut self, spec: &ColumnSpec, values: &[f64], number: usize) -> Result<(), String> {
        if values.len() < spec.width() {
            return Err(format!("line {number}: {} values, the layout needs {}", values.len(), spec.width()));
        }
        let value = |column| spec.index_of(column).map(|index| values[index]);
        let triple = |columns: [Column; 3]| -> Option<[f64; 3]> {
            Some([value(columns[0])?, value(columns[1])?, value(columns[2])?])
        };
        let [x, y, z] = triple([Column::X, Column::Y, Column::Z]).ok_or("layout without x, y, z")?;
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            return Err(format!("line {number}: non-finite coordinate"));
        }
        self.positions.push(DVec3::new(x, y, z));
        self.intensities.extend(value(Column::Intensity));
        self.colors.extend(triple([Column::Red, Column::Green, Column::Blue]));
        if let Some([nx, ny, nz]) = triple([Column::NormalX, Column::NormalY, Column::NormalZ]) {
            self.normals.push(Vec3::new(nx as f32, ny as f32, nz as f32));
        }
        Ok(())
    }

    fn into_point_cloud(self, spec: &ColumnSpec) -> Result<PointCloud, String> {
        if self.positions.is_empty() {
            return Err("no point lines found (expected x y z per line)".into());
        }
        let has = |column| spec.index_of(column).is_some();
        let colors = if has(Column::Red) { Some(colors_to_8_bit(&self.colors)?) } else { None };
        Ok(PointCloud {
            intensities: normalise_intensities(&self.intensities),
            colors,
            normals: has(Column::NormalX).then_some(self.normals),
            ..PointCloud::from_positions(self.positions)
        })
    }
}

fn colors_to_8_bit(raw: &[[f64; 3]]) -> Result<Vec<[u8; 3]>, String> {
    let channels = raw.iter().flatten();
    if let Some(bad) = channels.clone().find(|c| !(c.is_finite() && **c >= 0.0)) {
        return Err(format!("colour value {bad} is not a non-negative number"));
    }
    let max = channels.fold(0.0, |max: f64, &c| max.max(c));
    let scale = match max {
        m if m <= 1.0 => 255.0,
        m if m <= 255.0 => 1.0,
        m if m <= 65535.0 => 1.0 / 257.0,
        m => return Err(format!("colour value {m} is beyond 16 bits")),
    };
    Ok(raw.iter().map(|rgb| rgb.map(|c| (c * scale).round() as u8)).collect())
}
