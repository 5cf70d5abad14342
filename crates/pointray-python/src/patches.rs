//! `Patches`: a prepped point set, as `pointray prep` writes it to a patch store.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{IntoPyArray, PyArrayMethods};
use pointray_patches::{PatchSet, ScanStructure, patch_store};
use pyo3::prelude::*;

use crate::errors::to_python;

/// One MLS patch per distinct point: what `prep` makes and the renderers draw.
#[pyclass(module = "pointray", frozen)]
pub struct Patches {
    pub set: Arc<PatchSet>,
    /// The scan structure prep found, which the store records.
    pub scan: ScanStructure,
}

#[pymethods]
impl Patches {
    /// Reads a patch store (`.patches`) that `pointray prep` or `Patches.save` wrote.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let read = || {
            Ok::<_, patch_store::StoreError>((patch_store::read(&path)?, patch_store::describe(&path)?.scan))
        };
        let (set, scan) = py.detach(read).map_err(|e| to_python(&e))?;
        Ok(Self { set: Arc::new(set), scan })
    }

    /// Writes a patch store, atomically; it never replaces the file it was read from.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| patch_store::write_with_scan(&path, &self.set, &self.scan)).map_err(|e| to_python(&e))
    }

    fn __len__(&self) -> usize {
        self.set.len()
    }

    fn __repr__(&self) -> String {
        format!("Patches({} patches)", self.set.len())
    }

    /// The recentring offset: `centers = local + offset`, in float64.
    #[getter]
    fn offset(&self) -> [f64; 3] {
        self.set.offset.to_array()
    }

    /// (N, 3) float64: each patch's origin, in the input's coordinates: its point moved along
    /// the normal onto the fitted surface.
    #[getter]
    fn centers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let offset = self.set.offset;
        let values: Vec<f64> =
            self.set.hot.iter().flat_map(|hot| (hot.origin().as_dvec3() + offset).to_array()).collect();
        Ok(values.into_pyarray(py).reshape([self.set.len(), 3])?.into_any())
    }

    /// (N, 3) float32 unit normals.
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let values: Vec<f32> = self.set.hot.iter().flat_map(|hot| hot.normal().to_array()).collect();
        Ok(values.into_pyarray(py).reshape([self.set.len(), 3])?.into_any())
    }

    /// (N,) float32 support radii.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let values: Vec<f32> = self.set.hot.iter().map(|hot| hot.radius()).collect();
        values.into_pyarray(py).into_any()
    }
}
