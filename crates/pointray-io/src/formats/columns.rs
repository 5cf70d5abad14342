//! What each column of a headerless record holds: text point files (`.xyz`, `.pts`, `.txt`,
//! `.csv`) and raw float32 sweeps (`.bin`) name nothing themselves, so a [`ColumnSpec`]
//! (from the user, a CSV header line, or a layout the file's shape implies) says it.

use std::str::FromStr;

/// What one column holds.
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
    /// The scan line (beam) of a spinning sensor: a small non-negative integer.
    Ring,
    /// An ASPRS (LAS) classification code: an integer from 0 to 255.
    Classification,
    /// A column we do not use (written `_` or `skip` in a spec).
    Skip,
}

/// The names a spec may use, for messages.
pub const COLUMN_NAMES: &str = "x y z intensity (i) r g b nx ny nz ring classification _ (skip)";

impl Column {
    /// The short name a spec uses.
    fn name(self) -> &'static str {
        match self {
            Self::X => "x",
            Self::Y => "y",
            Self::Z => "z",
            Self::Intensity => "intensity",
            Self::Red => "r",
            Self::Green => "g",
            Self::Blue => "b",
            Self::NormalX => "nx",
            Self::NormalY => "ny",
            Self::NormalZ => "nz",
            Self::Ring => "ring",
            Self::Classification => "classification",
            Self::Skip => "_",
        }
    }

    /// Accepts the short spec names and the usual long header names, any case.
    pub(crate) fn from_name(name: &str) -> Option<Self> {
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
            "ring" | "ring_index" => Self::Ring,
            "classification" | "class" => Self::Classification,
            "_" | "skip" => Self::Skip,
            _ => return None,
        };
        Some(column)
    }
}

/// The meaning of each column, e.g. `"x,y,z,intensity,ring"`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColumnSpec {
    columns: Vec<Column>,
}

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum ColumnSpecError {
    #[error("column spec {spec:?}: unknown column name {name:?}; known: {COLUMN_NAMES}")]
    UnknownName { spec: String, name: String },
    #[error("column spec {spec:?}: column {column:?} appears twice")]
    Duplicate { spec: String, column: Column },
    #[error("column spec {spec:?}: needs x, y and z")]
    MissingPosition { spec: String },
    #[error("column spec {spec:?}: {group} must be given together")]
    PartialGroup { spec: String, group: &'static str },
}

impl ColumnSpec {
    /// Parses names separated by commas, semicolons or whitespace. `x`, `y` and `z` are
    /// required; `r g b` and `nx ny nz` come as complete groups.
    pub fn parse(spec: &str) -> Result<Self, ColumnSpecError> {
        let columns = spec
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|name| !name.is_empty())
            .map(|name| {
                Column::from_name(name)
                    .ok_or_else(|| ColumnSpecError::UnknownName { spec: spec.into(), name: name.into() })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::validated(columns, spec)
    }

    /// The layout of `count` columns when nothing names them, if that count implies one:
    /// 3 = x y z; 4 = x y z i; 6 = x y z r g b; 7 = x y z i r g b (PTS);
    /// 9 = x y z r g b nx ny nz; 10 = x y z i r g b nx ny nz. Other counts have no one
    /// reading (5 could end in a ring, a classification or a time), so they need a spec.
    pub fn for_column_count(count: usize) -> Option<Self> {
        use Column::*;
        let columns = match count {
            3 => vec![X, Y, Z],
            4 => vec![X, Y, Z, Intensity],
            6 => vec![X, Y, Z, Red, Green, Blue],
            7 => vec![X, Y, Z, Intensity, Red, Green, Blue],
            9 => vec![X, Y, Z, Red, Green, Blue, NormalX, NormalY, NormalZ],
            10 => vec![X, Y, Z, Intensity, Red, Green, Blue, NormalX, NormalY, NormalZ],
            _ => return None,
        };
        Some(Self { columns })
    }

    /// A layout this crate knows to be valid (x, y and z present, groups whole).
    pub(crate) fn known(columns: &[Column]) -> Self {
        Self { columns: columns.to_vec() }
    }

    /// A header line's names; names we do not know become skipped columns.
    pub(crate) fn from_header(names: &[&str], line: &str) -> Result<Self, ColumnSpecError> {
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

    /// Where `column` sits, if the spec has it.
    pub fn index_of(&self, column: Column) -> Option<usize> {
        self.columns.iter().position(|c| *c == column)
    }

    /// How many values a record holds.
    pub fn width(&self) -> usize {
        self.columns.len()
    }
}

impl FromStr for ColumnSpec {
    type Err = ColumnSpecError;

    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        Self::parse(spec)
    }
}

/// The spec written back as names, e.g. `x,y,z,intensity,ring`.
impl std::fmt::Display for ColumnSpec {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<&str> = self.columns.iter().map(|column| column.name()).collect();
        formatter.write_str(&names.join(","))
    }
}
