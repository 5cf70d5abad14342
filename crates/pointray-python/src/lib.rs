//! The `pointray._native` extension module: the Rust side of the `pointray` Python package.
//! The package's Python layer (`python/pointray/`) gives it its documented API; this layer
//! converts between numpy arrays and the workspace's types and releases the GIL for long calls.

mod errors;
mod read;

use pyo3::prelude::*;

#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("PointrayError", module.py().get_type::<errors::PointrayError>())?;
    module.add_function(wrap_pyfunction!(read::read, module)?)?;
    Ok(())
}
