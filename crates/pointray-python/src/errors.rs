//! Errors cross into Python as `pointray.PointrayError`, carrying the message the command
//! line prints for the same failure.

use pointray_render::error_line;
use pyo3::PyErr;
use pyo3::create_exception;
use pyo3::exceptions::PyException;

create_exception!(
    pointray,
    PointrayError,
    PyException,
    "A pointray operation failed; the message names the file and the problem."
);

/// The error as the command line prints it.
pub fn to_python(error: &(dyn std::error::Error + 'static)) -> PyErr {
    PointrayError::new_err(error_line(error))
}
