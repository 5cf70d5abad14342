//! The cli crate's integration tests, in one binary so that CI links it once.

mod common;

mod autzen_scene;
mod bad_input;
mod geo_offset;
mod intensity_material;
mod prep_robustness_flags;
mod radius_fidelity;
mod scan_measures;
mod scene_prep_keys;
