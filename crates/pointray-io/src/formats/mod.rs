//! One module per file format; `read_point_cloud` and `read_triangle_mesh` pick the reader.

mod column_rows;
pub mod columns;
pub mod copc;
mod copc_chunks;
mod copc_hierarchy;
pub mod copc_octree;
pub mod detect;
mod dispatch;
pub mod e57;
pub(crate) mod intensity;
pub mod las;
pub(crate) mod las_chunks;
pub mod laser_origins;
pub mod obj;
pub mod ouster_metadata;
pub mod pcd;
pub mod ply;
pub mod raw_bin;
pub(crate) mod raw_bin_chunks;
pub mod sweep_order;
pub mod xyz;

pub use columns::ColumnSpec;
pub use dispatch::{
    FileFormat, detect_file_format, read_point_cloud, read_point_cloud_with, read_triangle_mesh,
};

/// A parser library's message with the standard library's words for text that is not UTF-8
/// replaced by ours.
pub(crate) fn in_plain_words(message: &str) -> String {
    message.replace("stream did not contain valid UTF-8", "it is not UTF-8 text")
}
