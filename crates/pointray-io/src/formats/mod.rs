//! One module per file format.

pub mod detect;
pub mod e57;
mod intensity;
pub mod kitti;
pub mod las;
pub mod pcd;
pub mod ply;
pub mod xyz;
