//! `PointAttributes`: what `prep` takes beside the positions, one value a point, read from
//! numpy arrays and checked when made; their lengths are checked against the positions when
//! they meet.

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{float_column, float_rows, integer_column};

/// Per-point `colors` (sRGB, N x 3), `normals` (N x 3), `intensity` (0..1), `classification`
/// (ASPRS codes) and `ring` (scan line), each sensor's origin (`sensor_origins`, N x 3), and
/// where the one sensor stood (`sensor_position`).
#[pyclass(module = "pointray._native", frozen)]
pub struct PointAttributes {
    colors: Option<Vec<[u8; 3]>>,
    normals: Option<Vec<Vec3>>,
    intensities: Option<Vec<f32>>,
    classifications: Option<Vec<u8>>,
    rings: Option<Vec<u16>>,
    sensor_position: Option<DVec3>,
    sensor_origins: Option<Vec<DVec3>>,
}

#[pymethods]
impl PointAttributes {
    #[new]
    #[pyo3(signature = (
        *, colors=None, normals=None, intensity=None, classification=None, ring=None,
        sensor_position=None, sensor_origins=None
    ))]
    fn new(
        colors: Option<&Bound<'_, PyAny>>,
        normals: Option<&Bound<'_, PyAny>>,
        intensity: Option<&Bound<'_, PyAny>>,
        classification: Option<&Bound<'_, PyAny>>,
        ring: Option<&Bound<'_, PyAny>>,
        sensor_position: Option<[f64; 3]>,
        sensor_origins: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        Ok(Self {
            colors: colors.map(read_colors).transpose()?,
            normals: normals.map(read_normals).transpose()?,
            intensities: intensity.map(read_intensities).transpose()?,
            classifications: classification.map(read_classes).transpose()?,
            rings: ring.map(read_rings).transpose()?,
            sensor_position: sensor_position.map(finite_position).transpose()?,
            sensor_origins: sensor_origins.map(read_origins).transpose()?,
        })
    }
}

impl PointAttributes {
    /// The cloud of `positions` with these attributes; one that does not hold a value for
    /// each point raises `ValueError` naming it.
    pub fn cloud_of(&self, positions: Vec<DVec3>) -> PyResult<PointCloud> {
        let count = positions.len();
        for (name, length) in [
            ("sensor_origins", self.sensor_origins.as_ref().map(Vec::len)),
            ("colors", self.colors.as_ref().map(Vec::len)),
            ("normals", self.normals.as_ref().map(Vec::len)),
            ("intensity", self.intensities.as_ref().map(Vec::len)),
            ("classification", self.classifications.as_ref().map(Vec::len)),
            ("ring", self.rings.as_ref().map(Vec::len)),
        ] {
            if let Some(length) = length.filter(|&length| length != count) {
                return Err(PyValueError::new_err(format!("{name} has {length} values for {count} points")));
            }
        }
        Ok(PointCloud {
            colors: self.colors.clone(),
            normals: self.normals.clone(),
            intensities: self.intensities.clone(),
            classifications: self.classifications.clone(),
            rings: self.rings.clone(),
            sensor_position: self.sensor_position,
            sensor_origins: self.sensor_origins.clone(),
            ..PointCloud::from_positions(positions)
        })
    }
}

fn read_colors(array: &Bound<'_, PyAny>) -> PyResult<Vec<[u8; 3]>> {
    let rows = float_rows::<3>("colors", array)?;
    Ok(rows.iter().map(|rgb| rgb.map(|c| c.clamp(0.0, 255.0) as u8)).collect())
}

fn read_normals(array: &Bound<'_, PyAny>) -> PyResult<Vec<Vec3>> {
    let rows = float_rows::<3>("normals", array)?;
    Ok(rows.into_iter().map(|n| Vec3::from_array(n.map(|c| c as f32))).collect())
}

fn read_intensities(array: &Bound<'_, PyAny>) -> PyResult<Vec<f32>> {
    Ok(float_column("intensity", array)?.into_iter().map(|v| v as f32).collect())
}

fn read_classes(array: &Bound<'_, PyAny>) -> PyResult<Vec<u8>> {
    Ok(integer_column("classification", array, 256)?.into_iter().map(|v| v as u8).collect())
}

fn read_rings(array: &Bound<'_, PyAny>) -> PyResult<Vec<u16>> {
    Ok(integer_column("ring", array, 65536)?.into_iter().map(|v| v as u16).collect())
}

fn read_origins(array: &Bound<'_, PyAny>) -> PyResult<Vec<DVec3>> {
    Ok(float_rows::<3>("sensor_origins", array)?.into_iter().map(DVec3::from_array).collect())
}

fn finite_position(position: [f64; 3]) -> PyResult<DVec3> {
    if !position.iter().all(|c| c.is_finite()) {
        return Err(PyValueError::new_err(format!("sensor_position {position:?} is not finite")));
    }
    Ok(DVec3::from_array(position))
}
