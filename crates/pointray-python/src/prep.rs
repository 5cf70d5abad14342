//! `prep(positions, ...)`: numpy arrays to patches, with the command line's settings.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use pointray_patches::PrepSettings;
use pointray_surface::NoProgress;
use pointray_surface::input_validation::validate_settings;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Deserialize;

use crate::arrays::{float_column, float_rows, integer_column};
use crate::errors::{PointrayError, to_python};
use crate::patches::Patches;
use crate::toml_values::to_toml;

/// `pointray prep`'s settings, parsed and checked when made: the keywords are the flags' names
/// (`k`, `radius`, `sensor`, ...) and go through the parser of a scene file's `prep` table, so
/// a bad one raises `PointrayError` with the words a scene file gets.
#[pyclass(module = "pointray._native", frozen)]
pub struct PrepOptions {
    pub settings: PrepSettings,
}

#[pymethods]
impl PrepOptions {
    #[new]
    #[pyo3(signature = (**settings))]
    fn new(settings: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let table = match settings {
            Some(settings) => to_toml(settings.as_any())?,
            None => toml::Value::Table(toml::Table::new()),
        };
        let settings = PrepSettings::deserialize(table)
            .map_err(|e| PointrayError::new_err(format!("prep settings: {}", e.message())))?;
        validate_settings(&settings).map_err(|e| to_python(&e))?;
        Ok(Self { settings })
    }
}

/// Preps `positions` (N, 3) with optional per-point `attributes` (`colors`, `intensity`,
/// `classification`, `normals`, `ring`, `sensor_position`, `sensor_origins`) and `options`.
#[pyfunction]
#[pyo3(signature = (positions, attributes, options))]
pub fn prep(
    py: Python<'_>,
    positions: &Bound<'_, PyAny>,
    attributes: &Bound<'_, PyDict>,
    options: &PrepOptions,
) -> PyResult<Patches> {
    let settings = options.settings;
    let cloud = point_cloud(positions, attributes)?;
    let (set, _report) = py
        .detach(|| pointray_surface::prep_owned(cloud, &settings, &NoProgress))
        .map_err(|e| to_python(&e))?;
    Ok(Patches { set: Arc::new(set) })
}

fn point_cloud(positions: &Bound<'_, PyAny>, attributes: &Bound<'_, PyDict>) -> PyResult<PointCloud> {
    let positions: Vec<DVec3> =
        float_rows::<3>("positions", positions)?.into_iter().map(DVec3::from_array).collect();
    let mut cloud = PointCloud::from_positions(positions);
    let count = cloud.len();
    let per_point = |name: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
        Ok(attributes.get_item(name)?.filter(|value| !value.is_none()))
    };
    if let Some(colors) = per_point("colors")? {
        let rows = float_rows::<3>("colors", &colors)?;
        cloud.colors = Some(rows.iter().map(|rgb| rgb.map(|c| c.clamp(0.0, 255.0) as u8)).collect());
    }
    if let Some(normals) = per_point("normals")? {
        cloud.normals = Some(
            float_rows::<3>("normals", &normals)?
                .into_iter()
                .map(|n| Vec3::from_array(n.map(|c| c as f32)))
                .collect(),
        );
    }
    if let Some(intensity) = per_point("intensity")? {
        cloud.intensities =
            Some(float_column("intensity", &intensity)?.into_iter().map(|v| v as f32).collect());
    }
    if let Some(classes) = per_point("classification")? {
        cloud.classifications =
            Some(integer_column("classification", &classes, 256)?.into_iter().map(|v| v as u8).collect());
    }
    if let Some(rings) = per_point("ring")? {
        cloud.rings = Some(integer_column("ring", &rings, 65536)?.into_iter().map(|v| v as u16).collect());
    }
    if let Some(sensor) = per_point("sensor_position")? {
        let position: [f64; 3] = sensor.extract()?;
        if !position.iter().all(|c| c.is_finite()) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "sensor_position {position:?} is not finite"
            )));
        }
        cloud.sensor_position = Some(DVec3::from_array(position));
    }
    if let Some(origins) = per_point("sensor_origins")? {
        let rows = float_rows::<3>("sensor_origins", &origins)?;
        cloud.sensor_origins = Some(rows.into_iter().map(DVec3::from_array).collect());
    }
    for (name, length) in [
        ("sensor_origins", cloud.sensor_origins.as_ref().map(Vec::len)),
        ("colors", cloud.colors.as_ref().map(Vec::len)),
        ("normals", cloud.normals.as_ref().map(Vec::len)),
        ("intensity", cloud.intensities.as_ref().map(Vec::len)),
        ("classification", cloud.classifications.as_ref().map(Vec::len)),
        ("ring", cloud.rings.as_ref().map(Vec::len)),
    ] {
        if let Some(length) = length.filter(|&length| length != count) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "{name} has {length} values for {count} points"
            )));
        }
    }
    Ok(cloud)
}
