//! Prep in tiles, for clouds too large to prep at once: the cloud is cut along its Morton
//! curve (`curve_span`, `cloud_subset`), each tile is prepped with the halo of points it
//! needs from its neighbours (`halo_reach`, `halo_test`, `reach_cells`) and the tiles' patches
//! are put back in order (`patch_map`, `tiled_prep`). Streamed prep does the same from disk
//! in bounded memory: the out-of-core sort (`point_records`, `sorted_points`,
//! `out_of_core_sort`), the plan of tiles within a budget (`streamed_tiles`,
//! `stream_budget`), the spool of patches (`spool`) and the whole run (`streamed_prep`).
//! A tile job of a cluster writes a tile file (`tile_file`), and `merge` joins them; jobs may
//! share one sort kept in a folder (`kept_sort`).
//!
//! It may use the core pipeline at the crate root (`prep` on one tile, its checks, Morton
//! codes and neighbours, progress), `pointray-patches` (the patch set and its store),
//! `pointray-kernels` and `pointray-io`; it does not use `scan`.

mod cloud_subset;
mod curve_span;
mod disk_room;
mod halo_reach;
mod halo_test;
pub mod kept_sort;
pub mod merge;
mod octree_sort;
mod out_of_core_sort;
mod patch_map;
mod point_records;
mod reach_cells;
mod sorted_points;
mod spool;
mod stream_budget;
pub mod stream_error;
pub mod streamed_prep;
pub mod streamed_tiles;
pub mod tile_file;
pub mod tiled_prep;
