//! Reading and writing what pointray consumes and produces: point clouds, triangle
//! meshes and images. Each file format lives in `formats/`, one module per format.

pub mod atomic_write;
pub mod error;
pub mod formats;
pub mod image_output;
pub mod point_cloud;
pub mod triangle_mesh;

pub use atomic_write::{ensure_not_same_file, write_atomically};
pub use error::IoError;
pub use point_cloud::PointCloud;
pub use triangle_mesh::TriangleMesh;
