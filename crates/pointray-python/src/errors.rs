//! Errors cross into Python as `pointray.PointrayError`, carrying the message the command
//! line prints for the same failure.

use pyo3::PyErr;
use pyo3::create_exception;
use pyo3::exceptions::PyException;

create_exception!(
    pointray,
    PointrayError,
    PyException,
    "A pointray operation failed; the message names the file and the problem."
);

/// The error and its causes on one line, each cause added only when the text does not already
/// quote it (the command line's form).
pub fn to_python(error: &(dyn std::error::Error + 'static)) -> PyErr {
    let mut text = String::new();
    let mut cause: Option<&(dyn std::error::Error + 'static)> = Some(error);
    while let Some(current) = cause {
        let message = current.to_string();
        if !text.contains(&message) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&message);
        }
        cause = current.source();
    }
    PointrayError::new_err(text)
}
