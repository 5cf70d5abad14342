//! From a point set to MLS quadratic patches (SPEC.md §2): the offline half of pointray.

pub mod patch_set;

pub use patch_set::{PatchSet, PrepParams};
