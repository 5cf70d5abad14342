//! From a point set to MLS quadratic patches (METHOD.md §2): the offline half of pointray.
//!
//! Three rooms:
//! - the crate root holds the core prep pipeline (`prep`): input checks, neighbours,
//!   normals and their orientation, support radii, the quadratic fit and the boxes;
//! - `scan` shapes patches by a LiDAR scan's line structure;
//! - `tiles` preps a cloud in tiles: halos, the out-of-core sort, streamed prep, tile jobs
//!   and their merge.
//!
//! The patches it makes, and the store it writes them to, are `pointray-patches`'.

mod cold_records;
mod component_signs;
pub mod density_radius;
mod duplicate_clusters;
pub mod duplicates;
pub mod input_validation;
pub mod morton;
mod nearest_cells;
pub mod neighbors;
pub mod normals;
pub mod orientation;
mod orientation_tree;
mod outlier_removal;
pub mod peak_memory;
mod prep;
mod prep_error;
pub mod prep_memory;
mod prep_progress;
mod prep_report;
mod quadratic_fit;
pub mod sampling;
pub mod scan;
mod shaped_patches;
mod stage_clock;
mod support_radius;
pub mod tiles;
mod trimmed_centre;
pub mod uneven_sampling;
mod wendland;

pub use prep::{PREP_REVISION, TileContext, prep, prep_in_context, prep_owned};
pub use prep_error::PrepError;
pub use prep_progress::{NoProgress, PrepProgress, Stage};
pub use prep_report::{FitCounts, PrepReport, RadiusFallbacks, ScanSummary};
pub use quadratic_fit::{FitKind, PatchFit};
pub use sampling::{sample_mesh, sample_mesh_part};
pub use trimmed_centre::trimmed_centre;
