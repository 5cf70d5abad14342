//! A loaded scene drawn by the renderer a program chose (`BackendChoice`): the Vulkan ray
//! tracer or the CPU renderer, which draw the same image. The programs' edges (the command
//! line, the viewer and the Python module) open one `Backend` and render through it; its
//! errors are `BackendError`s.

mod backend;
mod backend_choice;
mod environment;
mod error;
mod error_line;
mod map_caster;
mod missing_tiles;
mod ready_scene;

pub use backend::Backend;
pub use backend_choice::BackendChoice;
pub use environment::device_options_from_environment;
pub use error::BackendError;
pub use error_line::error_line;
pub use map_caster::GpuMapCaster;
pub use missing_tiles::missing_tiles;
pub use pointray_vulkan::{DeviceOptions, DeviceSelector};
pub use ready_scene::{ReadyScene, Tracer};
