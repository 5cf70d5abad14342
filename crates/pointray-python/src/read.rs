//! `read(path)`: a points file to numpy arrays.

use std::path::{Path, PathBuf};

use glam::DVec3;
use numpy::{IntoPyArray, PyArrayMethods};
use pointray_io::formats::{ColumnSpec, read_point_cloud_with};
use pointray_io::{PointCloud, SweepPoses, sweep_map};
use pointray_scene::UpAxis;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::float_rows;
use crate::errors::to_python;

/// Reads several sweeps and places them by their sensor poses (`poses`: a KITTI poses file,
/// or one 4x4 a line) into one map; each point keeps its sweep's sensor origin and line.
#[pyfunction]
#[pyo3(signature = (paths, poses, columns=None))]
pub fn read_sweeps<'py>(
    py: Python<'py>,
    paths: Vec<PathBuf>,
    poses: PathBuf,
    columns: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let columns = columns.map(|text| text.parse::<ColumnSpec>().map_err(|e| to_python(&e))).transpose()?;
    let map = py
        .detach(|| {
            let placed = SweepPoses::read(&poses)?.for_sweeps(&paths, &poses)?;
            let sweeps = paths
                .iter()
                .map(|path| read_point_cloud_with(path, columns.as_ref()))
                .collect::<Result<Vec<_>, _>>()?;
            let names: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
            sweep_map(sweeps, &placed, &names)
        })
        .map_err(|error| to_python(&error))?;
    let fields = cloud_to_dict(py, map)?;
    fields.set_item("up_axis", "z")?;
    Ok(fields)
}

/// Reads a points file; returns a dict of numpy arrays (absent fields are `None`).
#[pyfunction]
#[pyo3(signature = (path, columns=None))]
pub fn read<'py>(py: Python<'py>, path: PathBuf, columns: Option<&str>) -> PyResult<Bound<'py, PyDict>> {
    let columns = columns.map(|text| text.parse::<ColumnSpec>().map_err(|e| to_python(&e))).transpose()?;
    let cloud =
        py.detach(|| read_point_cloud_with(&path, columns.as_ref())).map_err(|error| to_python(&error))?;
    let fields = cloud_to_dict(py, cloud)?;
    let up = match UpAxis::conventional(&path) {
        UpAxis::Y => "y",
        UpAxis::Z => "z",
    };
    fields.set_item("up_axis", up)?;
    Ok(fields)
}

fn cloud_to_dict(py: Python<'_>, cloud: PointCloud) -> PyResult<Bound<'_, PyDict>> {
    let fields = PyDict::new(py);
    let count = cloud.len();
    let positions: Vec<f64> = cloud.positions.iter().flat_map(|p| p.to_array()).collect();
    fields.set_item("positions", positions.into_pyarray(py).reshape([count, 3])?)?;
    let normals = cloud.normals.map(|n| n.iter().flat_map(|v| v.to_array()).collect::<Vec<f32>>());
    fields.set_item("normals", normals.map(|n| n.into_pyarray(py).reshape([count, 3])).transpose()?)?;
    let colors = cloud.colors.map(|c| c.into_iter().flatten().collect::<Vec<u8>>());
    fields.set_item("colors", colors.map(|c| c.into_pyarray(py).reshape([count, 3])).transpose()?)?;
    fields.set_item("intensity", cloud.intensities.map(|v| v.into_pyarray(py)))?;
    fields.set_item("classification", cloud.classifications.map(|v| v.into_pyarray(py)))?;
    fields.set_item("ring", cloud.rings.map(|v| v.into_pyarray(py)))?;
    fields.set_item("sensor_position", cloud.sensor_position.map(|p| p.to_array()))?;
    let origins = cloud.sensor_origins.map(|o| o.iter().flat_map(|p| p.to_array()).collect::<Vec<f64>>());
    fields
        .set_item("sensor_origins", origins.map(|o| o.into_pyarray(py).reshape([count, 3])).transpose()?)?;
    Ok(fields)
}

/// The offset `prep` recentres `positions` (N, 3) on (`input = local + offset`).
#[pyfunction]
pub fn recentring_offset(positions: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    let positions: Vec<DVec3> =
        float_rows::<3>("positions", positions)?.into_iter().map(DVec3::from_array).collect();
    Ok(pointray_surface::trimmed_centre(&positions).to_array())
}
