//! The `pointray._native` extension module: the Rust side of the `pointray` Python package.
//! The package's Python layer (`python/pointray/`) gives it its documented API; this layer
//! converts between numpy arrays and the workspace's types and releases the GIL for long calls.

mod arrays;
mod devices;
mod errors;
mod image_out;
mod image_settings;
mod patches;
mod point_attributes;
mod prep;
mod read;
mod render;
mod render_options;
mod render_source;
mod scene_text;
mod tile_jobs;
mod toml_values;

use pyo3::prelude::*;

#[global_allocator]
static ALLOCATOR: pointray_io::HugePageAllocator = pointray_io::HugePageAllocator;

#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("PointrayError", module.py().get_type::<errors::PointrayError>())?;
    module.add_class::<patches::Patches>()?;
    module.add_class::<image_settings::ImageSettings>()?;
    module.add_class::<render_options::RenderOptions>()?;
    module.add_class::<render_source::RenderSource>()?;
    module.add_class::<prep::PrepOptions>()?;
    module.add_class::<point_attributes::PointAttributes>()?;
    module.add_function(wrap_pyfunction!(read::read, module)?)?;
    module.add_function(wrap_pyfunction!(read::read_sweeps, module)?)?;
    module.add_function(wrap_pyfunction!(read::recentring_offset, module)?)?;
    module.add_function(wrap_pyfunction!(prep::prep, module)?)?;
    module.add_function(wrap_pyfunction!(tile_jobs::prep_tile, module)?)?;
    module.add_function(wrap_pyfunction!(tile_jobs::merge_tiles, module)?)?;
    module.add_function(wrap_pyfunction!(render::render, module)?)?;
    module.add_function(wrap_pyfunction!(scene_text::scene_to_toml, module)?)?;
    module.add_function(wrap_pyfunction!(scene_text::scene_from_toml, module)?)?;
    module.add_function(wrap_pyfunction!(image_out::encode_png, module)?)?;
    module.add_function(wrap_pyfunction!(image_out::save_image, module)?)?;
    module.add_function(wrap_pyfunction!(devices::devices, module)?)?;
    Ok(())
}
