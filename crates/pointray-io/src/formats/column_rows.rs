//! Records of numbers whose meaning a `ColumnSpec` gives (text lines, raw float records),
//! gathered and turned into a `PointCloud` once all are read and their ranges are known.

use glam::{DVec3, Vec3};

use super::columns::{Column, ColumnSpec};
use super::intensity::IntensityRange;
use crate::PointCloud;

/// Where each attribute sits in a record; looked up once, not per record.
struct RecordLayout {
    width: usize,
    position: [usize; 3],
    intensity: Option<usize>,
    color: Option<[usize; 3]>,
    normal: Option<[usize; 3]>,
    ring: Option<usize>,
    classification: Option<usize>,
}

impl RecordLayout {
    fn of(spec: &ColumnSpec) -> Self {
        let at = |column| spec.index_of(column);
        let triple = |columns: [Column; 3]| Some([at(columns[0])?, at(columns[1])?, at(columns[2])?]);
        Self {
            width: spec.width(),
            // A spec always has x, y and z; see `ColumnSpec::validated`.
            position: triple([Column::X, Column::Y, Column::Z]).unwrap_or([0, 1, 2]),
            intensity: at(Column::Intensity),
            color: triple([Column::Red, Column::Green, Column::Blue]),
            normal: triple([Column::NormalX, Column::NormalY, Column::NormalZ]),
            ring: at(Column::Ring),
            classification: at(Column::Classification),
        }
    }
}

/// Raw values, converted only at the end, when the value ranges are known.
pub(crate) struct ColumnRows {
    layout: RecordLayout,
    positions: Vec<DVec3>,
    intensities: Vec<f64>,
    colors: Vec<[f64; 3]>,
    normals: Vec<Vec3>,
    rings: Vec<u16>,
    classifications: Vec<u8>,
}

impl ColumnRows {
    pub fn new(spec: &ColumnSpec, capacity: usize) -> Self {
        Self {
            layout: RecordLayout::of(spec),
            positions: Vec::with_capacity(capacity),
            intensities: Vec::new(),
            colors: Vec::new(),
            normals: Vec::new(),
            rings: Vec::new(),
            classifications: Vec::new(),
        }
    }

    /// Adds one record; an error says what is wrong with it (the caller says where).
    pub fn push(&mut self, values: &[f64]) -> Result<(), String> {
        let layout = &self.layout;
        if values.len() != layout.width {
            return Err(format!("{} values, the layout needs {}", values.len(), layout.width));
        }
        let position = DVec3::from(layout.position.map(|index| values[index]));
        if !position.is_finite() {
            return Err(format!("non-finite coordinate {position}"));
        }
        if let Some(index) = layout.ring {
            self.rings.push(whole_number("ring", values[index], u16::MAX.into())? as u16);
        }
        if let Some(index) = layout.classification {
            self.classifications.push(whole_number("classification", values[index], u8::MAX.into())? as u8);
        }
        self.positions.push(position);
        self.intensities.extend(layout.intensity.map(|index| values[index]));
        self.colors.extend(layout.color.map(|indices| indices.map(|index| values[index])));
        if let Some(indices) = layout.normal {
            self.normals.push(Vec3::from(indices.map(|index| values[index] as f32)));
        }
        Ok(())
    }

    pub fn into_point_cloud(self) -> Result<PointCloud, String> {
        let mut range = IntensityRange::default();
        self.include_intensities(&mut range);
        self.into_point_cloud_scaled(&range)
    }

    /// Widens `range` by these records' intensities: a file read in chunks scales each
    /// chunk by the whole file's range.
    pub fn include_intensities(&self, range: &mut IntensityRange) {
        self.intensities.iter().for_each(|&value| range.include(value));
    }

    /// The cloud, with intensities scaled as `range` (the whole file's) says.
    pub fn into_point_cloud_scaled(self, range: &IntensityRange) -> Result<PointCloud, String> {
        let layout = &self.layout;
        let colors = if layout.color.is_some() { Some(colors_to_8_bit(&self.colors)?) } else { None };
        let scale = layout.intensity.and(range.scale());
        Ok(PointCloud {
            intensities: scale
                .map(|scale| self.intensities.iter().map(|&value| scale.apply(value)).collect()),
            colors,
            normals: layout.normal.is_some().then_some(self.normals),
            rings: layout.ring.is_some().then_some(self.rings),
            classifications: layout.classification.is_some().then_some(self.classifications),
            ..PointCloud::from_positions(self.positions)
        })
    }
}

/// `value` as a whole number in `[0, max]`, or an error naming the column.
fn whole_number(column: &str, value: f64, max: f64) -> Result<f64, String> {
    if value.fract() == 0.0 && (0.0..=max).contains(&value) {
        Ok(value)
    } else {
        Err(format!("{column} {value} is not a whole number from 0 to {max}"))
    }
}

/// Colours are 8-bit (0-255); all within [0, 1] are taken as float colours and scaled, and
/// 16-bit colours (up to 65535) are scaled down.
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
