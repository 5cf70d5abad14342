//! `RenderSource`: what one `render` call draws, typed and checked when it is made: a scene
//! file's text with the point sets it holds in memory, or points shown as `pointray render
//! POINTS` shows them.

use std::path::PathBuf;
use std::sync::Arc;

use pointray_patches::PatchSet;
use pointray_scene::{PointsScene, SceneFile, UpAxis};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::errors::to_python;
use crate::patches::Patches;

/// Point sets given in memory, by object index (`LoadOptions::in_memory`).
pub type InMemory = Vec<(usize, Arc<PatchSet>)>;

/// A scene, the point sets it holds in memory, and the axis that a camera given in the file's
/// coordinates is stood upright by.
#[pyclass(module = "pointray._native", frozen)]
pub struct RenderSource {
    pub file: SceneFile,
    pub in_memory: InMemory,
    pub up: UpAxis,
}

#[pymethods]
impl RenderSource {
    /// A scene file's `text`, its relative paths taken from `anchor`'s folder, with
    /// `in_memory`'s patches standing for the point sets of those object indices.
    #[staticmethod]
    fn scene(text: &str, anchor: PathBuf, in_memory: Vec<(usize, PyRef<'_, Patches>)>) -> PyResult<Self> {
        let file = SceneFile::parse(text, &anchor).map_err(|e| to_python(&e))?;
        let in_memory = in_memory.into_iter().map(|(index, patches)| (index, patches.set.clone())).collect();
        Ok(Self { file, in_memory, up: UpAxis::Y })
    }

    /// Points from `points_file`, or `patches` prepped in memory, stood upright by `up`
    /// (`"y"` or `"z"`; by default the file format's convention, and `"y"` for patches), on a
    /// `floor`, coloured by `color`, lit by one light and framed.
    #[staticmethod]
    #[pyo3(signature = (*, points_file=None, patches=None, up=None, floor=true, color="auto"))]
    fn points(
        points_file: Option<PathBuf>,
        patches: Option<PyRef<'_, Patches>>,
        up: Option<&str>,
        floor: bool,
        color: &str,
    ) -> PyResult<Self> {
        let mut look = points_file.as_deref().map_or_else(PointsScene::default, PointsScene::conventional);
        if let Some(up) = up {
            look.up = up.parse().map_err(PyValueError::new_err)?;
        }
        look.floor = floor;
        look.color_source = color.parse().map_err(PyValueError::new_err)?;
        let name = points_file.unwrap_or_else(|| PathBuf::from("(points from Python)"));
        let in_memory = patches.map(|patches| vec![(0, patches.set.clone())]).unwrap_or_default();
        Ok(Self { file: look.scene_file(&name), in_memory, up: look.up })
    }
}
