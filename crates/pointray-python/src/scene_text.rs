//! A `Scene` built in Python as nested dicts, to and from the scene file's TOML, checked by the
//! scene file's own parser.

use std::path::PathBuf;

use pointray_scene::SceneFile;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{PointrayError, to_python};
use crate::toml_values::{to_python as toml_to_python, to_toml};

/// The scene as TOML text, checked as a scene file is (`anchor` names it in messages and
/// anchors its relative paths).
#[pyfunction]
pub fn scene_to_toml(scene: &Bound<'_, PyDict>, anchor: PathBuf) -> PyResult<String> {
    let text =
        toml::to_string(&to_toml(scene.as_any())?).map_err(|e| PointrayError::new_err(e.to_string()))?;
    SceneFile::parse(&text, &anchor).map_err(|e| to_python(&e))?;
    Ok(text)
}

/// TOML text (a scene file's) as nested dicts, after the scene file's checks.
#[pyfunction]
pub fn scene_from_toml<'py>(py: Python<'py>, text: &str, anchor: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    SceneFile::parse(text, &anchor).map_err(|e| to_python(&e))?;
    let value: toml::Value = toml::from_str(text).map_err(|e| PointrayError::new_err(e.to_string()))?;
    toml_to_python(py, &value)
}
