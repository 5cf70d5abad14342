//! `prep(positions, ...)`: numpy arrays to patches, with the command line's settings.

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;
use pointray_patches::{PrepSettings, patch_store};
use pointray_surface::NoProgress;
use pointray_surface::input_validation::validate_settings;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Deserialize;

use crate::arrays::float_rows;
use crate::errors::{PointrayError, to_python};
use crate::patches::Patches;
use crate::point_attributes::PointAttributes;
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

/// Preps `positions` (N, 3) with their `attributes` and `options`.
#[pyfunction]
#[pyo3(signature = (positions, attributes, options))]
pub fn prep(
    py: Python<'_>,
    positions: &Bound<'_, PyAny>,
    attributes: &PointAttributes,
    options: &PrepOptions,
) -> PyResult<Patches> {
    let settings = options.settings;
    let positions = float_rows::<3>("positions", positions)?.into_iter().map(DVec3::from_array).collect();
    let cloud = attributes.cloud_of(positions)?;
    let (set, report) = py
        .detach(|| pointray_surface::prep_owned(cloud, &settings, &NoProgress))
        .map_err(|e| to_python(&e))?;
    // The patches as a store holds them, as `Patches.load` and the renderers' loader give them.
    let stored = py.detach(|| patch_store::as_stored(&set, Path::new("(points from Python)")));
    Ok(Patches { set: Arc::new(stored.map_err(|e| to_python(&e))?), scan: report.scan_structure() })
}
