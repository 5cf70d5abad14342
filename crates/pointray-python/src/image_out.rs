//! A rendered image out of Python: written as `pointray render` writes it (8-bit sRGB PNG or
//! linear float EXR, atomically), or as PNG bytes for notebooks' inline display.

use std::path::PathBuf;

use glam::Vec3;
use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pointray_io::IoError;
use pointray_io::image_output::{encode_png_srgb, write_exr_linear, write_png_srgb};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::to_python;

/// (H, W, 3 or 4) float32 linear RGB(A) to PNG bytes; alpha is dropped.
#[pyfunction]
pub fn encode_png<'py>(py: Python<'py>, image: PyReadonlyArray3<'py, f32>) -> PyResult<Bound<'py, PyBytes>> {
    let (width, height, linear) = linear_rgb(&image)?;
    let bytes = encode_png_srgb(width, height, &linear).map_err(|e| to_python(&e))?;
    Ok(PyBytes::new(py, &bytes))
}

/// Writes (H, W, 3 or 4) float32 linear RGB(A) to `path`: `.png` or `.exr`, as `render -o`.
#[pyfunction]
pub fn save_image(py: Python<'_>, image: PyReadonlyArray3<'_, f32>, path: PathBuf) -> PyResult<()> {
    let (width, height, linear) = linear_rgb(&image)?;
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    py.detach(|| match extension.as_deref() {
        Some("png") => write_png_srgb(&path, width, height, &linear),
        Some("exr") => write_exr_linear(&path, width, height, &linear),
        _ => Err(IoError::unwritable(&path, "an image is written as .png or .exr")),
    })
    .map_err(|e| to_python(&e))
}

fn linear_rgb(image: &PyReadonlyArray3<'_, f32>) -> PyResult<(u32, u32, Vec<Vec3>)> {
    let &[height, width, channels] = image.shape() else { unreachable!("three dimensions") };
    if !matches!(channels, 3 | 4) {
        return Err(PyValueError::new_err(format!(
            "expected (H, W, 3) or (H, W, 4), got {:?}",
            image.shape()
        )));
    }
    let pixels = image.as_array();
    let linear = pixels.rows().into_iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    Ok((width as u32, height as u32, linear))
}
