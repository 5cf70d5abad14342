//! The patch data model (METHOD.md §2): a prepped point set's MLS patches (`PatchSet`), the
//! records it holds them in, the settings `prep` made them with, the patch store file that
//! caches them, and how they split into tiles. The renderers stand on this crate; the prep
//! pipeline (`pointray-surface`) writes what it holds.
//!
//! It may use `pointray-kernels` (the record types) and `pointray-io` (files), nothing above.

pub mod coarse_level;
pub mod compact_patches;
pub mod geometry_range;
mod parallel_checksum;
pub mod patch_bounds;
mod patch_checks;
pub mod patch_records;
pub mod patch_set;
pub mod patch_store;
pub mod patch_store_in_place;
mod patch_store_write;
pub mod patch_tiles;
pub mod prep_settings;
pub mod scan_structure;
pub mod stored_coarse;

pub use patch_records::PatchRecords;
pub use patch_set::PatchSet;
pub use prep_settings::{BoxKind, InvalidSetting, OutlierFilter, PrepSettings, RadiusMode, ScanMode};
pub use scan_structure::ScanStructure;
