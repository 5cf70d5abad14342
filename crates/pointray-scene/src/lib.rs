//! What gets rendered: camera, lights, background and objects (point sets and meshes),
//! the settings of one render and the frame that comes back.

pub mod camera;
pub mod frame;
pub mod light;
pub mod material;
pub mod render_settings;
pub mod scene;

pub use camera::Camera;
pub use frame::Frame;
pub use light::Light;
pub use material::Material;
pub use render_settings::{AcceptanceTest, BufferLayout, RenderSettings};
pub use scene::{Background, Geometry, Scene, SceneObject};
