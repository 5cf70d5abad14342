//! `ImageSettings`: the scene's `[render]` settings one `render` call overrides, each checked
//! as its flag is.

use pointray_scene::integrator::Integrator;
use pointray_scene::{HotRecords, RenderSetting, RenderSettings};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A `None` leaves the scene's setting as it is.
#[pyclass(module = "pointray._native", frozen)]
#[derive(Clone)]
pub struct ImageSettings {
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
    #[pyo3(get)]
    pub patches_per_box: Option<u32>,
    pub hot_records: Option<HotRecords>,
}

#[pymethods]
impl ImageSettings {
    /// Checks each setting as its flag is checked; a bad one raises `ValueError` naming it.
    #[new]
    #[pyo3(signature = (*, width=None, height=None, spp=None, max_depth=None, shadows=None, integrator=None, seed=None, patches_per_box=None, hot_records=None))]
    #[allow(clippy::too_many_arguments, reason = "Python's keyword arguments, each a setting")]
    fn new(
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        max_depth: Option<u32>,
        shadows: Option<bool>,
        integrator: Option<&str>,
        seed: Option<&Bound<'_, PyAny>>,
        patches_per_box: Option<u32>,
        hot_records: Option<&str>,
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
            patches_per_box: checked(RenderSetting::PatchesPerBox, "patches_per_box", patches_per_box)?,
            hot_records: hot_records
                .map(|name| name.parse().map_err(|e| PyValueError::new_err(format!("hot_records: {e}"))))
                .transpose()?,
        })
    }
}

impl ImageSettings {
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
        settings.patches_per_box = self.patches_per_box.or(settings.patches_per_box);
        settings.hot_records = self.hot_records.or(settings.hot_records);
    }
}

fn checked(setting: RenderSetting, key: &str, value: Option<u32>) -> PyResult<Option<u32>> {
    value
        .map(|value| {
            setting.check(value).map_err(|problem| PyValueError::new_err(format!("{key}: {problem}")))
        })
        .transpose()
}
