//! What gets rendered: camera, lights, background and objects (point sets and meshes),
//! the settings of one render and the image that comes back.
//!
//! The feature `load` (on by default) adds scene files and their loading (`scene_file` and
//! the `*_spec` tables it is made of, `load`, `point_sets`, `render_space`, `demo`), which
//! prep the point clouds a scene names and so stand on `pointray-surface`. The renderers take this crate without it: what they draw is a
//! `Scene`, whose point sets are `pointray-patches`' `PatchSet`s.

pub mod background;
#[cfg(feature = "load")]
pub mod background_spec;
pub mod bounds;
#[cfg(feature = "load")]
mod cache_folder;
#[cfg(feature = "load")]
mod checks;
pub mod classification_palette;
#[cfg(feature = "load")]
pub mod color_ramp;
#[cfg(feature = "load")]
pub mod demo;
mod emissive_meshes;
pub mod error;
#[cfg(feature = "load")]
pub mod file_camera;
mod framing;
pub mod ground;
pub mod hot_records;
pub mod image_output;
pub mod integrator;
pub mod light;
#[cfg(feature = "load")]
pub mod load;
pub mod material;
#[cfg(feature = "load")]
pub mod material_spec;
#[cfg(feature = "load")]
pub mod object_spec;
pub mod orbit;
#[cfg(feature = "load")]
pub mod point_sets;
#[cfg(feature = "load")]
pub mod points_scene;
pub mod procedural;
pub mod render_settings;
#[cfg(feature = "load")]
pub mod render_space;
pub mod rendered_image;
pub mod scene;
#[cfg(feature = "load")]
pub mod scene_file;
pub mod sun_sky;
#[cfg(feature = "load")]
pub mod transform_spec;

pub use background::Background;
#[cfg(feature = "load")]
pub use cache_folder::clean_cache;
#[cfg(feature = "load")]
pub use demo::{demo_scene, load_demo};
pub use error::SceneError;
#[cfg(feature = "load")]
pub use file_camera::FileCamera;
pub use hot_records::HotRecords;
pub use image_output::{AovSelection, write_image};
pub use integrator::Integrator;
pub use light::Light;
#[cfg(feature = "load")]
pub use load::{LoadOptions, LoadedScene, load_scene, load_scene_file};
pub use material::{Material, SurfaceKind};
pub use orbit::orbit_camera;
#[cfg(feature = "load")]
pub use point_sets::{PointSetOrigin, ReadRequest};
pub use pointray_kernels::Camera;
pub use pointray_kernels::PatchAcceptance;
#[cfg(feature = "load")]
pub use points_scene::{PointsScene, UpAxis};
pub use render_settings::{BufferLayout, RenderSetting, RenderSettings};
#[cfg(feature = "load")]
pub use render_space::RenderSpace;
pub use rendered_image::RenderedImage;
pub use scene::{Geometry, Scene, SceneObject};
#[cfg(feature = "load")]
pub use scene_file::SceneFile;
pub use sun_sky::SunSky;
