//! `RenderOptions`: the settings of one `render` call, typed and checked when they are made,
//! with the command line's words, so that `render` reads fields rather than a dict's keys.

use pointray_io::MemoryBudget;
use pointray_render::{BackendChoice, DeviceSelector};
use pointray_scene::integrator::Integrator;
use pointray_scene::scene_file::CameraSpec;
use pointray_scene::{RenderSetting, RenderSettings};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Deserialize;

use crate::errors::PointrayError;
use crate::toml_values::to_toml;

/// What `pointray.render`'s keywords become. A `None` leaves the scene's `[render]` setting
/// as it is; `camera` is a scene file's camera table, in the file's coordinates.
#[pyclass(module = "pointray._native", frozen)]
pub struct RenderOptions {
    #[pyo3(get)]
    pub width: Option<u32>,
    #[pyo3(get)]
    pub height: Option<u32>,
    #[pyo3(get)]
    pub spp: Option<u32>,
    #[pyo3(get)]
    pub max_depth: Option<u32>,
    #[pyo3(get)]
    pub shadows: Option<bool>,
    pub integrator: Option<Integrator>,
    #[pyo3(get)]
    pub seed: Option<u32>,
    pub backend: BackendChoice,
    pub device: DeviceSelector,
    /// The GPU memory budget in bytes, never 0.
    #[pyo3(get)]
    pub gpu_memory: Option<u64>,
    pub camera: Option<CameraSpec>,
    #[pyo3(get)]
    pub denoise: bool,
}

#[pymethods]
impl RenderOptions {
    /// Checks each setting as its flag is checked; a bad one raises `ValueError` naming it.
    #[new]
    #[pyo3(signature = (
        *, width=None, height=None, spp=None, max_depth=None, shadows=None, integrator=None,
        seed=None, backend="auto", device="auto", gpu_memory=None, camera=None, denoise=false
    ))]
    #[expect(clippy::too_many_arguments, reason = "one keyword a setting, as `pointray.render` takes them")]
    fn new(
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        max_depth: Option<u32>,
        shadows: Option<bool>,
        integrator: Option<&str>,
        seed: Option<&Bound<'_, PyAny>>,
        backend: &str,
        device: &str,
        gpu_memory: Option<&Bound<'_, PyAny>>,
        camera: Option<&Bound<'_, PyDict>>,
        denoise: bool,
    ) -> PyResult<Self> {
        Ok(Self {
            width: checked(RenderSetting::Width, "width", width)?,
            height: checked(RenderSetting::Height, "height", height)?,
            spp: checked(RenderSetting::SamplesPerPixel, "spp", spp)?,
            max_depth: checked(RenderSetting::MaxDepth, "max_depth", max_depth)?,
            shadows,
            integrator: integrator
                .map(|name| name.parse().map_err(|e| PyValueError::new_err(format!("integrator: {e}"))))
                .transpose()?,
            seed: seed
                .map(|seed| {
                    seed.extract::<u32>()
                        .map_err(|_| PyValueError::new_err("seed: a whole number from 0 to 2^32 - 1"))
                })
                .transpose()?,
            backend: backend.parse().map_err(PyValueError::new_err)?,
            device: device.parse().map_err(|e| PyValueError::new_err(format!("device: {e}")))?,
            gpu_memory: gpu_memory.map(memory_budget).transpose()?,
            camera: camera.map(camera_spec).transpose()?,
            denoise,
        })
    }
}

impl RenderOptions {
    /// The file's `[render]` settings with these on top.
    pub fn apply(&self, settings: &mut RenderSettings) {
        let overrides = [
            (self.width, &mut settings.width),
            (self.height, &mut settings.height),
            (self.spp, &mut settings.samples_per_pixel),
            (self.max_depth, &mut settings.max_depth),
            (self.seed, &mut settings.seed),
        ];
        for (value, target) in overrides {
            if let Some(value) = value {
                *target = value;
            }
        }
        settings.shadows = self.shadows.unwrap_or(settings.shadows);
        settings.integrator = self.integrator.unwrap_or(settings.integrator);
    }
}

fn checked(setting: RenderSetting, key: &str, value: Option<u32>) -> PyResult<Option<u32>> {
    value
        .map(|value| {
            setting.check(value).map_err(|problem| PyValueError::new_err(format!("{key}: {problem}")))
        })
        .transpose()
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

/// A scene file's camera table, through the scene file's own parser.
fn camera_spec(table: &Bound<'_, PyDict>) -> PyResult<CameraSpec> {
    CameraSpec::deserialize(to_toml(table.as_any())?)
        .map_err(|e| PointrayError::new_err(format!("camera: {}", e.message())))
}
