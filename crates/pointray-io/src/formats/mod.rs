//! One module per file format; `read_point_cloud` and `read_triangle_mesh` pick the reader.

pub mod detect;
mod dispatch;
pub mod e57;
mod intensity;
pub mod kitti;
pub mod las;
pub mod obj;
pub mod pcd;
pub mod ply;
pub mod xyz;

pub use dispatch::{FileFormat, detect_file_format, read_point_cloud, read_triangle_mesh};
