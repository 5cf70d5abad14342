//! `render(...)`: a scene, a points file or prepped patches to numpy images, on the CPU or a
//! Vulkan device, through the same loading and renderers as `pointray render`.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{IntoPyArray, PyArrayMethods};
use pointray_denoise::{DenoiseSettings, denoise};
use pointray_io::MemoryBudget;
use pointray_patches::PatchSet;
use pointray_render::{Backend, DeviceOptions, device_options_from_environment, error_line, missing_tiles};
use pointray_scene::load::{LoadOptions, load_scene_file};
use pointray_scene::{PointsScene, RenderedImage, SceneFile, UpAxis};
use pointray_vulkan::TileResidency;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::{PointrayError, to_python};
use crate::patches::Patches;
use crate::render_options::RenderOptions;

/// Renders `source` with `options`; returns the image and, on request, its AOVs.
#[pyfunction]
pub fn render<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyDict>,
    options: &RenderOptions,
) -> PyResult<Bound<'py, PyDict>> {
    let SceneSource { mut file, in_memory, up } = scene_source(source)?;
    if let Some(spec) = options.camera.clone() {
        file.camera = Some(up.camera_to_scene(spec));
    }
    let mut settings = file.render_settings().map_err(|e| to_python(&e))?;
    options.apply(&mut settings);
    settings.check_memory(&MemoryBudget::of_this_machine()).map_err(PointrayError::new_err)?;
    let (backend, device, gpu_memory, denoised) =
        (options.backend, options.device.clone(), options.gpu_memory, options.denoise);
    let (image, residency) = py
        .detach(|| -> Result<(RenderedImage, Option<TileResidency>), String> {
            let load_options = LoadOptions { in_memory: &in_memory, ..LoadOptions::default() };
            let loaded = load_scene_file(&file, &load_options).map_err(|e| error_line(&e))?;
            let device_options = DeviceOptions { gpu_memory, ..device_options_from_environment() };
            let backend = Backend::open(backend, &device, device_options).map_err(|e| error_line(&e))?;
            let (mut image, residency) =
                backend.render(&loaded.scene, &settings).map_err(|e| error_line(&e))?;
            if denoised {
                image = denoise(&image, &DenoiseSettings::default());
            }
            image.scale_depth(loaded.space.scale as f32);
            Ok((image, residency))
        })
        .map_err(PointrayError::new_err)?;
    if let Some(missing) = residency.as_ref().and_then(missing_tiles) {
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &std::ffi::CString::new(missing)?, 1)?;
    }
    image_to_dict(py, image)
}

/// Point sets given in memory, by object index (`LoadOptions::in_memory`).
type InMemory = Vec<(usize, Arc<PatchSet>)>;

/// What a source describes: a scene file, the point sets it holds in memory by object index,
/// and the axis that a camera given in the file's coordinates is stood upright by.
struct SceneSource {
    file: SceneFile,
    in_memory: InMemory,
    up: UpAxis,
}

fn scene_source(source: &Bound<'_, PyDict>) -> PyResult<SceneSource> {
    if let Some(text) = text_option(source, "scene")? {
        let anchor = path_option(source, "anchor")?.unwrap_or_else(|| PathBuf::from("(scene from Python)"));
        let file = SceneFile::parse(&text, &anchor).map_err(|e| to_python(&e))?;
        let in_memory = match source.get_item("in_memory")? {
            Some(list) => list
                .cast::<PyList>()?
                .iter()
                .map(|item| {
                    let (index, patches): (usize, PyRef<'_, Patches>) = item.extract()?;
                    Ok((index, patches.set.clone()))
                })
                .collect::<PyResult<_>>()?,
            None => Vec::new(),
        };
        return Ok(SceneSource { file, in_memory, up: UpAxis::Y });
    }
    let points = path_option(source, "points_file")?;
    let patches = match source.get_item("patches")? {
        Some(patches) => Some(patches.extract::<PyRef<'_, Patches>>()?.set.clone()),
        None => None,
    };
    let name = points.clone().unwrap_or_else(|| PathBuf::from("(points from Python)"));
    let mut look = points.as_deref().map_or_else(PointsScene::default, PointsScene::conventional);
    if let Some(up) = text_option(source, "up")? {
        look.up = up.parse().map_err(PyValueError::new_err)?;
    }
    look.floor = flag_option(source, "floor")?.unwrap_or(look.floor);
    if let Some(color) = text_option(source, "color")? {
        look.color_source = color.parse().map_err(PyValueError::new_err)?;
    }
    let in_memory = patches.map(|set| vec![(0, set)]).unwrap_or_default();
    Ok(SceneSource { file: look.scene_file(&name), in_memory, up: look.up })
}

/// `dict[key]` unless absent or `None`.
fn option<'py>(dict: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
    Ok(dict.get_item(key)?.filter(|value| !value.is_none()))
}

fn text_option(dict: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<String>> {
    option(dict, key)?.map(|value| value.extract::<String>()).transpose()
}

fn path_option(dict: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<PathBuf>> {
    option(dict, key)?.map(|value| value.extract::<PathBuf>()).transpose()
}

fn flag_option(dict: &Bound<'_, PyDict>, key: &str) -> PyResult<Option<bool>> {
    option(dict, key)?.map(|value| value.extract::<bool>()).transpose()
}

/// The image as (H, W, 4) float32, linear RGB with alpha 1 where a primary ray hit the scene,
/// and the AOVs as (H, W, ...) arrays (the albedo under the path integrator only).
fn image_to_dict(py: Python<'_>, image: RenderedImage) -> PyResult<Bound<'_, PyDict>> {
    let (width, height) = (image.width as usize, image.height as usize);
    let hit = image.hit_mask();
    let rgba: Vec<f32> = image
        .color
        .iter()
        .zip(&hit)
        .flat_map(|(color, &hit)| [color.x, color.y, color.z, if hit { 1.0 } else { 0.0 }])
        .collect();
    let result = PyDict::new(py);
    result.set_item("image", rgba.into_pyarray(py).reshape([height, width, 4])?)?;
    result.set_item("depth", image.depth.into_pyarray(py).reshape([height, width])?)?;
    let normals: Vec<f32> = image.normal.iter().flat_map(|n| n.to_array()).collect();
    result.set_item("normal", normals.into_pyarray(py).reshape([height, width, 3])?)?;
    let ids = |ids: Vec<u32>| {
        ids.into_iter()
            .map(|id| if id == RenderedImage::MISS { -1 } else { i64::from(id) })
            .collect::<Vec<i64>>()
    };
    result.set_item("instance", ids(image.instance_id).into_pyarray(py).reshape([height, width])?)?;
    result.set_item("primitive", ids(image.primitive_id).into_pyarray(py).reshape([height, width])?)?;
    if let Some(albedo) = image.albedo {
        let albedo: Vec<f32> = albedo.iter().flat_map(|a| a.to_array()).collect();
        result.set_item("albedo", albedo.into_pyarray(py).reshape([height, width, 3])?)?;
    }
    Ok(result)
}
