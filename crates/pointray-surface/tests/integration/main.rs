//! The surface crate's integration tests, in one binary so that CI links it once.

mod analytic_surfaces;
mod bunny;
mod color_interpolation;
mod common;
mod compact_store;
mod copc_prep;
mod density_adaptive_radii;
mod disk_scale;
mod normals_analytic;
mod normals_duplicates;
mod normals_scans;
mod normals_support;
mod outlier_removal;
mod patch_store_files;
mod prep_attributes;
mod prep_bad_input;
mod scan_aware;
mod streamed_prep;
mod tiled_prep;
