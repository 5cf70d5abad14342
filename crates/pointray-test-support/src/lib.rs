//! What the crates' tests share (a dev-dependency only): the checkout's data files, a Vulkan
//! renderer or a clear failure under CI, image comparison, meshes and scenes built in code,
//! points files prepped into patches, PCD files, and Monte Carlo error bounds.

#[cfg(feature = "scenes")]
pub mod analytic_scenes;
mod data;
mod device;
#[cfg(feature = "scenes")]
pub mod floor_scenes;
mod images;
#[cfg(feature = "meshes")]
mod meshes;
mod monte_carlo;
#[cfg(feature = "pcd")]
mod pcd;
#[cfg(feature = "prep")]
mod prepped;

pub use data::{data_dir, data_file};
#[cfg(feature = "vulkan")]
pub use device::{assert_no_validation_messages, vulkan_renderer};
pub use device::{in_ci, skip_without_device};
pub use images::{largest_byte_difference, psnr_bytes};
#[cfg(feature = "images")]
pub use images::{largest_color_difference, psnr_colors};
#[cfg(feature = "meshes")]
pub use meshes::sphere_mesh;
pub use monte_carlo::{Estimate, estimate};
#[cfg(feature = "pcd")]
pub use pcd::write_pcd_f32;
#[cfg(feature = "prep")]
pub use prepped::{prepped_points, prepped_points_with_boxes};
