//! What gets rendered: camera, lights, background and objects (point sets and meshes),
//! the settings of one render and the image that comes back.

pub mod bounds;
mod checks;
pub mod classification_palette;
pub mod color_ramp;
pub mod demo;
pub mod error;
mod framing;
pub mod ground;
pub mod image_output;
pub mod integrator;
pub mod light;
pub mod load;
pub mod material;
pub mod material_spec;
pub mod object_spec;
pub mod orbit;
pub mod point_sets;
pub mod points_scene;
pub mod procedural;
pub mod render_settings;
pub mod render_space;
pub mod rendered_image;
pub mod scene;
pub mod scene_file;
pub mod transform_spec;

pub use demo::{demo_scene, load_demo};
pub use error::SceneError;
pub use image_output::{AovSelection, write_image};
pub use integrator::Integrator;
pub use light::Light;
pub use load::{LoadOptions, LoadedScene, load_scene, load_scene_file};
pub use material::{Material, SurfaceKind};
pub use orbit::orbit_camera;
pub use point_sets::{PointSetOrigin, ReadRequest, clean_cache};
pub use pointray_kernels::Camera;
pub use pointray_kernels::PatchAcceptance;
pub use points_scene::{PointsScene, UpAxis};
pub use render_settings::{BufferLayout, RenderSetting, RenderSettings};
pub use render_space::RenderSpace;
pub use rendered_image::RenderedImage;
pub use scene::{Background, Geometry, Scene, SceneObject};
pub use scene_file::SceneFile;
