//! numpy arrays in: checked shapes and dtypes, with errors that say what was expected.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// An (N, `width`) array of any float or integer dtype, as rows of f64.
pub fn float_rows<const WIDTH: usize>(name: &str, array: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; WIDTH]>> {
    let flat = floats(name, array, WIDTH)?;
    Ok(flat.chunks_exact(WIDTH).map(|row| row.try_into().expect("rows of WIDTH")).collect())
}

/// An (N,) array of any float or integer dtype, as f64.
pub fn float_column(name: &str, array: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    floats(name, array, 1)
}

/// An (N,) array of unsigned integers below `limit`.
pub fn integer_column(name: &str, array: &Bound<'_, PyAny>, limit: u64) -> PyResult<Vec<u64>> {
    let values = floats(name, array, 1)?;
    values
        .iter()
        .map(|&v| {
            if v.fract() == 0.0 && (0.0..limit as f64).contains(&v) {
                Ok(v as u64)
            } else {
                Err(PyValueError::new_err(format!("{name}: {v} is not an integer in 0..{limit}")))
            }
        })
        .collect()
}

fn floats(name: &str, array: &Bound<'_, PyAny>, width: usize) -> PyResult<Vec<f64>> {
    let array = as_numeric_array(name, array)?;
    let shape = array.shape().to_vec();
    let fits = match width {
        1 => shape.len() == 1 || (shape.len() == 2 && shape[1] == 1),
        _ => shape.len() == 2 && shape[1] == width,
    };
    if !fits {
        let expected = if width == 1 { "(N,)".to_string() } else { format!("(N, {width})") };
        return Err(PyValueError::new_err(format!(
            "{name}: expected an array of shape {expected}, got {shape:?}"
        )));
    }
    let values = array.to_owned_array();
    Ok(values.iter().copied().collect())
}

/// Any real numeric numpy array (or sequence numpy can read) as f64.
fn as_numeric_array<'py>(name: &str, array: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = array.py();
    let numpy = py.import("numpy")?;
    let converted = numpy.call_method1("asarray", (array,))?;
    let kind: String = converted.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        let dtype = converted.getattr("dtype")?.str()?;
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a float or integer array, got dtype {dtype}"
        )));
    }
    let no_copy = pyo3::types::PyDict::new(py);
    no_copy.set_item("copy", false)?;
    let as_f64 = converted.call_method("astype", ("float64",), Some(&no_copy))?;
    Ok(as_f64.cast_into::<PyArrayDyn<f64>>()?)
}
