//! `render(...)`: a scene, a points file or prepped patches to numpy images, on the CPU or a
//! Vulkan device, through the same loading and renderers as `pointray render`.

use numpy::{IntoPyArray, PyArrayMethods};
use pointray_denoise::{DenoiseSettings, denoise};
use pointray_io::MemoryBudget;
use pointray_render::{Backend, DeviceOptions, device_options_from_environment, error_line, missing_tiles};
use pointray_scene::RenderedImage;
use pointray_scene::load::{LoadOptions, load_scene_file};
use pointray_vulkan::TileResidency;
use pyo3::exceptions::PyUserWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{PointrayError, to_python};
use crate::render_options::RenderOptions;
use crate::render_source::RenderSource;

/// Renders `source` with `options`; returns the image and, on request, its AOVs.
#[pyfunction]
pub fn render<'py>(
    py: Python<'py>,
    source: &RenderSource,
    options: &RenderOptions,
) -> PyResult<Bound<'py, PyDict>> {
    let mut file = source.file.clone();
    if let Some(camera) = &options.camera {
        file.camera = Some(source.up.camera_from_file(camera));
    }
    let mut settings = file.render_settings().map_err(|e| to_python(&e))?;
    options.image.apply(&mut settings);
    settings.check_memory(&MemoryBudget::of_this_machine()).map_err(PointrayError::new_err)?;
    let (backend, device, gpu_memory, denoised) =
        (options.backend, options.device.clone(), options.gpu_memory, options.denoise);
    let in_memory = &source.in_memory;
    let (image, residency) = py
        .detach(|| -> Result<(RenderedImage, Option<TileResidency>), String> {
            let load_options = LoadOptions { in_memory, ..LoadOptions::default() };
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
