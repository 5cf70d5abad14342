//! `devices()`: the Vulkan devices the loader sees, and whether each can render.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::to_python;

#[pyfunction]
pub fn devices(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    let devices = py.detach(pointray_vulkan::list_devices).map_err(|e| to_python(&e))?;
    devices
        .into_iter()
        .map(|device| {
            let entry = PyDict::new(py);
            entry.set_item("index", device.index)?;
            entry.set_item("name", &device.name)?;
            entry.set_item("type", device.device_type.to_string())?;
            entry.set_item("api_version", &device.api_version)?;
            entry.set_item("driver", &device.driver)?;
            entry.set_item("usable", device.rejection.is_none())?;
            entry.set_item("rejection", &device.rejection)?;
            entry.set_item("device_local_bytes", device.device_local_bytes)?;
            Ok(entry)
        })
        .collect()
}
