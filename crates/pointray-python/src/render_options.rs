//! `RenderOptions`: the settings of one `render` call, typed and checked when they are made,
//! with the command line's words, so that `render` reads fields rather than a dict's keys.

use pointray_io::MemoryBudget;
use pointray_render::{BackendChoice, DeviceSelector};
use pointray_scene::FileCamera;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Deserialize;

use crate::errors::PointrayError;
use crate::image_settings::ImageSettings;
use crate::toml_values::to_toml;

/// What `pointray.render`'s keywords become: the scene's `[render]` settings it overrides
/// (`image`), where it renders, the camera and the denoiser. `camera` is a scene file's camera
/// table, in the file's coordinates.
#[pyclass(module = "pointray._native", frozen)]
pub struct RenderOptions {
    pub image: ImageSettings,
    pub backend: BackendChoice,
    pub device: DeviceSelector,
    /// The GPU memory budget in bytes, never 0.
    #[pyo3(get)]
    pub gpu_memory: Option<u64>,
    pub camera: Option<FileCamera>,
    #[pyo3(get)]
    pub denoise: bool,
}

#[pymethods]
impl RenderOptions {
    /// Checks each setting as its flag is checked; a bad one raises `ValueError` naming it.
    #[new]
    #[pyo3(signature = (image, *, backend="auto", device="auto", gpu_memory=None, camera=None, denoise=false))]
    fn new(
        image: PyRef<'_, ImageSettings>,
        backend: &str,
        device: &str,
        gpu_memory: Option<&Bound<'_, PyAny>>,
        camera: Option<&Bound<'_, PyDict>>,
        denoise: bool,
    ) -> PyResult<Self> {
        Ok(Self {
            image: image.clone(),
            backend: backend.parse().map_err(PyValueError::new_err)?,
            device: device.parse().map_err(|e| PyValueError::new_err(format!("device: {e}")))?,
            gpu_memory: gpu_memory.map(memory_budget).transpose()?,
            camera: camera.map(file_camera).transpose()?,
            denoise,
        })
    }
}

/// Bytes given as an int or as a size such as `"40G"`.
fn memory_budget(value: &Bound<'_, PyAny>) -> PyResult<u64> {
    let bytes = match value.extract::<u64>() {
        Ok(bytes) => bytes,
        Err(_) => value.extract::<String>()?.parse::<MemoryBudget>().map_err(PyValueError::new_err)?.bytes,
    };
    if bytes == 0 {
        return Err(PyValueError::new_err("gpu_memory: 0 bytes is no budget; leave it out for the device's"));
    }
    Ok(bytes)
}

/// A scene file's camera table in the file's coordinates, read as `render --look-from` reads
/// its flags.
fn file_camera(table: &Bound<'_, PyDict>) -> PyResult<FileCamera> {
    FileCamera::deserialize(to_toml(table.as_any())?)
        .map_err(|e| PointrayError::new_err(format!("camera: {}", e.message())))
}
