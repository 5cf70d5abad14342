//! The PLY `vertex` element: which attributes a file carries, one record per vertex, and
//! the conversion of those records into a `PointCloud`.

use glam::DVec3;
use ply_rs_bw::ply::{ElementDef, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType};
use rayon::prelude::*;

use crate::PointCloud;

const POSITION: [&str; 3] = ["x", "y", "z"];
const NORMAL: [&str; 3] = ["nx", "ny", "nz"];
const COLOR: [&str; 3] = ["red", "green", "blue"];
const INTENSITY: [&str; 2] = ["intensity", "scalar_intensity"];
const RING: &str = "ring";
const CLASSIFICATION: &str = "classification";
const SENSOR: [&str; 3] = ["sensor_x", "sensor_y", "sensor_z"];

/// Which optional attributes the vertex element declares. Colours and intensities carry the
/// value that means 1 in their stored type, to bring them to a common scale.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct VertexLayout {
    pub has_normals: bool,
    pub color_unit: Option<f64>,
    pub intensity_unit: Option<f64>,
    pub has_rings: bool,
    pub has_classifications: bool,
    pub has_sensor_origins: bool,
}

impl VertexLayout {
    /// A layout that takes positions alone.
    pub fn positions_only() -> Self {
        Self {
            has_normals: false,
            color_unit: None,
            intensity_unit: None,
            has_rings: false,
            has_classifications: false,
            has_sensor_origins: false,
        }
    }

    /// Reads the layout from the header; x, y and z must be numeric scalars, a ring and a
    /// classification integers.
    pub fn from_element(element: &ElementDef) -> Result<Self, String> {
        for name in POSITION {
            scalar_type(element, name)?
                .ok_or_else(|| format!("the vertex element has no '{name}' property"))?;
        }
        Ok(Self {
            has_normals: group_type(element, &NORMAL)?.is_some(),
            color_unit: group_type(element, &COLOR)?.as_ref().map(unit_value),
            intensity_unit: first_scalar_type(element, &INTENSITY)?.as_ref().map(unit_value),
            has_rings: integer_type(element, RING)?,
            has_classifications: integer_type(element, CLASSIFICATION)?,
            has_sensor_origins: group_type(element, &SENSOR)?.is_some(),
        })
    }
}

/// The type of the named scalar property, `None` when absent, an error when it is a list.
fn scalar_type(element: &ElementDef, name: &str) -> Result<Option<ScalarType>, String> {
    match element.properties.get(name).map(|p| &p.data_type) {
        None => Ok(None),
        Some(PropertyType::Scalar(scalar)) => Ok(Some(scalar.clone())),
        Some(PropertyType::List(..)) => Err(format!("vertex property '{name}' is a list, expected a number")),
    }
}

/// Whether the named property is present; an error when it is not an integer.
fn integer_type(element: &ElementDef, name: &str) -> Result<bool, String> {
    match scalar_type(element, name)? {
        None => Ok(false),
        Some(ScalarType::Float | ScalarType::Double) => {
            Err(format!("vertex property '{name}' is a floating-point number, expected an integer type"))
        }
        Some(_) => Ok(true),
    }
}

/// A group such as (nx, ny, nz) counts only when all of its members are present.
fn group_type(element: &ElementDef, names: &[&str; 3]) -> Result<Option<ScalarType>, String> {
    let types =
        [scalar_type(element, names[0])?, scalar_type(element, names[1])?, scalar_type(element, names[2])?];
    Ok(match types {
        [Some(first), Some(_), Some(_)] => Some(first),
        _ => None,
    })
}

fn first_scalar_type(element: &ElementDef, names: &[&str]) -> Result<Option<ScalarType>, String> {
    for name in names {
        if let Some(scalar) = scalar_type(element, name)? {
            return Ok(Some(scalar));
        }
    }
    Ok(None)
}

/// One vertex as stored in the file, every attribute widened to f64 so that any numeric
/// property type can be read; attributes the file lacks stay zero.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct VertexRecord {
    pub position: [f64; 3],
    pub normal: [f64; 3],
    pub color: [f64; 3],
    pub intensity: f64,
    pub ring: f64,
    pub classification: f64,
    pub sensor: [f64; 3],
}

/// Which value of a record a property name refers to.
#[derive(Clone, Copy)]
pub(super) enum Field {
    Position(usize),
    Normal(usize),
    Color(usize),
    Intensity,
    Ring,
    Classification,
    Sensor(usize),
}

impl Field {
    pub(super) fn named(name: &str) -> Option<Self> {
        let index = |names: &[&str]| names.iter().position(|n| *n == name);
        index(&POSITION)
            .map(Self::Position)
            .or_else(|| index(&NORMAL).map(Self::Normal))
            .or_else(|| index(&COLOR).map(Self::Color))
            .or_else(|| index(&INTENSITY).map(|_| Self::Intensity))
            .or_else(|| (name == RING).then_some(Self::Ring))
            .or_else(|| (name == CLASSIFICATION).then_some(Self::Classification))
            .or_else(|| index(&SENSOR).map(Self::Sensor))
    }
}

impl VertexRecord {
    pub(super) fn slot(&mut self, field: Field) -> &mut f64 {
        match field {
            Field::Position(i) => &mut self.position[i],
            Field::Normal(i) => &mut self.normal[i],
            Field::Color(i) => &mut self.color[i],
            Field::Intensity => &mut self.intensity,
            Field::Ring => &mut self.ring,
            Field::Classification => &mut self.classification,
            Field::Sensor(i) => &mut self.sensor[i],
        }
    }

    fn get(&self, field: Field) -> f64 {
        match field {
            Field::Position(i) => self.position[i],
            Field::Normal(i) => self.normal[i],
            Field::Color(i) => self.color[i],
            Field::Intensity => self.intensity,
            Field::Ring => self.ring,
            Field::Classification => self.classification,
            Field::Sensor(i) => self.sensor[i],
        }
    }

    fn value(&self, name: &str) -> Option<f64> {
        Field::named(name).map(|field| self.get(field))
    }
}

impl PropertyAccess for VertexRecord {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if let (Some(field), Some(value)) = (Field::named(name), scalar_value(&property)) {
            *self.slot(field) = value;
        }
        PropertyAccessResult::Ignored
    }

    fn get_float(&self, name: &str) -> Option<f32> {
        self.value(name).map(|v| v as f32)
    }

    fn get_double(&self, name: &str) -> Option<f64> {
        self.value(name)
    }

    fn get_uchar(&self, name: &str) -> Option<u8> {
        self.value(name).map(|v| v as u8)
    }

    fn get_ushort(&self, name: &str) -> Option<u16> {
        self.value(name).map(|v| v as u16)
    }
}

fn scalar_value(property: &Property) -> Option<f64> {
    Some(match *property {
        Property::Char(v) => v.into(),
        Property::UChar(v) => v.into(),
        Property::Short(v) => v.into(),
        Property::UShort(v) => v.into(),
        Property::Int(v) => v.into(),
        Property::UInt(v) => v.into(),
        Property::Float(v) => v.into(),
        Property::Double(v) => v,
        _ => return None,
    })
}

/// The stored value that means 1: integers use their type's maximum (so uchar 255 and ushort
/// 65535 both mean 1); floating-point values are taken as already being on the unit scale.
fn unit_value(stored_as: &ScalarType) -> f64 {
    match stored_as {
        ScalarType::Char => i8::MAX.into(),
        ScalarType::UChar => u8::MAX.into(),
        ScalarType::Short => i16::MAX.into(),
        ScalarType::UShort => u16::MAX.into(),
        ScalarType::Int => i32::MAX.into(),
        ScalarType::UInt => u32::MAX.into(),
        ScalarType::Float | ScalarType::Double => 1.0,
    }
}

/// Turns the records into a cloud, refusing non-finite coordinates and sensor positions,
/// and rings or classifications out of their range.
pub(super) fn into_point_cloud(
    records: &[VertexRecord],
    layout: &VertexLayout,
) -> Result<PointCloud, String> {
    let divisor =
        layout.intensity_unit.map_or(1.0, |unit| intensity_divisor(largest_intensity(records, unit)));
    into_point_cloud_from(records, layout, 0, divisor)
}

/// As `into_point_cloud`, for records that start at point `first` of the file, with
/// intensities (on their type's unit scale) divided by `intensity_divisor`.
pub(super) fn into_point_cloud_from(
    records: &[VertexRecord],
    layout: &VertexLayout,
    first: u64,
    intensity_divisor: f64,
) -> Result<PointCloud, String> {
    let numbered = |problem: String| renumbered(problem, first);
    let positions = positions(records).map_err(numbered)?;
    let normals =
        layout.has_normals.then(|| records.par_iter().map(|r| DVec3::from(r.normal).as_vec3()).collect());
    let colors = layout
        .color_unit
        .map(|unit| records.par_iter().map(|r| r.color.map(|c| to_byte(c / unit))).collect());
    let intensities =
        layout.intensity_unit.map(|unit| normalised_intensities(records, unit, intensity_divisor));
    let rings = layout
        .has_rings
        .then(|| whole_numbers(records, RING, u16::MAX.into()))
        .transpose()
        .map_err(numbered)?;
    let classifications = layout
        .has_classifications
        .then(|| whole_numbers(records, CLASSIFICATION, u8::MAX.into()))
        .transpose()
        .map_err(numbered)?;
    let sensor_origins =
        layout.has_sensor_origins.then(|| sensor_origins(records)).transpose().map_err(numbered)?;
    Ok(PointCloud {
        positions,
        normals,
        colors,
        intensities,
        rings: rings.map(|values| values.into_iter().map(|v| v as u16).collect()),
        classifications: classifications.map(|values| values.into_iter().map(|v| v as u8).collect()),
        sensor_origins,
        sensor_position: None,
    })
}

/// The named integer property's values, each within `[0, max]`.
fn whole_numbers(records: &[VertexRecord], name: &str, max: f64) -> Result<Vec<f64>, String> {
    let field = Field::named(name).ok_or("not a vertex attribute")?;
    let values: Vec<f64> = records.par_iter().map(|record| record.get(field)).collect();
    match values.par_iter().position_first(|value| !(0.0..=max).contains(value)) {
        Some(index) => {
            Err(format!("point {index} has {name} {}; it must lie between 0 and {max}", values[index]))
        }
        None => Ok(values),
    }
}

fn sensor_origins(records: &[VertexRecord]) -> Result<Vec<DVec3>, String> {
    let origins: Vec<DVec3> = records.par_iter().map(|record| DVec3::from(record.sensor)).collect();
    match origins.par_iter().position_first(|origin| !origin.is_finite()) {
        Some(index) => Err(format!("point {index} has a non-finite sensor position {}", origins[index])),
        None => Ok(origins),
    }
}

/// The positions in file order; an error names the first point with a NaN or infinite coordinate.
pub(super) fn positions(records: &[VertexRecord]) -> Result<Vec<DVec3>, String> {
    checked_positions(records.par_iter().map(|record| DVec3::from(record.position)).collect())
}

/// `positions`, unless one has a NaN or infinite coordinate: then an error that names the
/// first such point.
pub(super) fn checked_positions(positions: Vec<DVec3>) -> Result<Vec<DVec3>, String> {
    match positions.par_iter().position_first(|position| !position.is_finite()) {
        Some(index) => Err(format!("point {index} has a non-finite coordinate {}", positions[index])),
        None => Ok(positions),
    }
}

fn to_byte(unit_channel: f64) -> u8 {
    (unit_channel.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// Errors name points by their index in the chunk; this makes it the file's.
pub(super) fn renumbered(problem: String, first: u64) -> String {
    match problem.strip_prefix("point ").and_then(|rest| rest.split_once(' ')) {
        Some((index, rest)) if first > 0 => match index.parse::<u64>() {
            Ok(index) => format!("point {} {rest}", first + index),
            Err(_) => problem,
        },
        _ => problem,
    }
}

/// The largest finite intensity on its type's unit scale (0 when none is above 0).
pub(super) fn largest_intensity(records: &[VertexRecord], unit_value: f64) -> f64 {
    records.par_iter().map(|r| r.intensity / unit_value).filter(|v| v.is_finite()).reduce(|| 0.0, f64::max)
}

/// Floating-point intensities outside [0, 1] (scanners write raw return strengths) are
/// divided by the largest one, so that their relative sizes survive.
pub(super) fn intensity_divisor(largest: f64) -> f64 {
    if largest > 1.0 { largest } else { 1.0 }
}

/// Intensities on [0, 1].
fn normalised_intensities(records: &[VertexRecord], unit_value: f64, divisor: f64) -> Vec<f32> {
    records.par_iter().map(|r| (r.intensity / unit_value / divisor).clamp(0.0, 1.0) as f32).collect()
}

/// Records for writing a cloud back out.
pub(super) fn records_of(cloud: &PointCloud) -> Vec<VertexRecord> {
    (0..cloud.len())
        .map(|i| VertexRecord {
            position: cloud.positions[i].to_array(),
            normal: cloud.normals.as_ref().map_or([0.0; 3], |n| n[i].as_dvec3().to_array()),
            color: cloud.colors.as_ref().map_or([0.0; 3], |c| c[i].map(f64::from)),
            intensity: cloud.intensities.as_ref().map_or(0.0, |v| v[i].into()),
            ring: cloud.rings.as_ref().map_or(0.0, |v| v[i].into()),
            classification: cloud.classifications.as_ref().map_or(0.0, |v| v[i].into()),
            sensor: cloud.sensor_origins.as_ref().map_or([0.0; 3], |v| v[i].to_array()),
        })
        .collect()
}
