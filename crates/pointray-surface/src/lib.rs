//! From a point set to MLS quadratic patches (SPEC.md §2): the offline half of pointray.

pub mod cold_records;
mod component_signs;
pub mod density_radius;
mod duplicate_clusters;
pub mod duplicates;
pub mod frame;
pub mod input_validation;
pub mod morton;
pub mod neighbors;
pub mod normals;
pub mod orientation;
mod orientation_tree;
pub mod outlier_removal;
pub mod patch_bounds;
pub mod patch_set;
pub mod patch_store;
pub mod prep;
pub mod prep_error;
pub mod prep_progress;
pub mod prep_report;
pub mod quadratic_fit;
pub mod sampling;
pub mod support_radius;
pub mod uneven_sampling;
pub mod wendland;

pub use density_radius::RadiusMode;
pub use frame::TangentFrame;
pub use outlier_removal::OutlierFilter;
pub use patch_bounds::BoxKind;
pub use patch_set::{PatchSet, PrepParams};
pub use prep::{PREP_REVISION, PrepOptions, prep};
pub use prep_error::PrepError;
pub use prep_progress::{NoProgress, PrepProgress, Stage};
pub use prep_report::{FitCounts, PrepReport, RadiusFallbacks};
pub use quadratic_fit::{FitKind, PatchFit};
pub use sampling::sample_mesh;
