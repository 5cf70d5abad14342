//! Reading and writing what pointray consumes and produces: point clouds, triangle
//! meshes and images. Each file format lives in `formats/`, one module per format.

pub mod atomic_write;
pub mod disk_space;
pub mod environment_image;
pub mod error;
pub mod file_roles;
pub mod formats;
pub mod huge_page_allocator;
pub mod image_output;
pub mod linear_image;
pub mod median;
pub mod memory_budget;
mod owner_lock;
pub mod point_cloud;
pub mod point_stream;
pub mod sweep_map;
pub mod sweep_poses;
pub mod temporaries;
pub mod triangle_mesh;

pub use atomic_write::{AtomicFile, write_atomically};
pub use environment_image::read_environment_image;
pub use error::IoError;
pub use file_roles::{
    ensure_not_same_file, ensure_outputs_spare_inputs, ensure_readable_file, ensure_writable_output,
    folder_of,
};
pub use huge_page_allocator::HugePageAllocator;
pub use linear_image::{LinearImage, read_linear_image, read_linear_image_within};
pub use median::median;
pub use memory_budget::{MemoryBudget, MemoryShortfall, available_memory};
pub use point_cloud::{AttributeBytes, PointCloud};
pub use point_stream::PointStream;
pub use sweep_map::sweep_map;
pub use sweep_poses::SweepPoses;
pub use triangle_mesh::TriangleMesh;
