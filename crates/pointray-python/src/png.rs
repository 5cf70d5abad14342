//! PNG bytes of a rendered image, encoded as `pointray render` writes PNGs (8-bit sRGB), for
//! notebooks' inline display.

use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pointray_io::image_output::encode_png_srgb;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::to_python;

/// (H, W, 3 or 4) float32 linear RGB(A) to PNG bytes; alpha is dropped.
#[pyfunction]
pub fn encode_png<'py>(py: Python<'py>, image: PyReadonlyArray3<'py, f32>) -> PyResult<Bound<'py, PyBytes>> {
    let [height, width, channels] = image.shape() else { unreachable!("three dimensions") };
    if !matches!(channels, 3 | 4) {
        return Err(PyValueError::new_err(format!(
            "expected (H, W, 3) or (H, W, 4), got {:?}",
            image.shape()
        )));
    }
    let pixels = image.as_array();
    let linear: Vec<glam::Vec3> = pixels
        .outer_iter()
        .flat_map(|row| row.outer_iter().map(|p| glam::Vec3::new(p[0], p[1], p[2])).collect::<Vec<_>>())
        .collect();
    let bytes = encode_png_srgb(*width as u32, *height as u32, &linear).map_err(|e| to_python(&e))?;
    Ok(PyBytes::new(py, &bytes))
}
