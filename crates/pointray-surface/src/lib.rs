//! From a point set to MLS quadratic patches (SPEC.md §2): the offline half of pointray.

pub mod duplicates;
pub mod morton;
pub mod neighbors;
pub mod normals;
pub mod orientation;
pub mod patch_set;

pub use patch_set::{PatchSet, PrepParams};
