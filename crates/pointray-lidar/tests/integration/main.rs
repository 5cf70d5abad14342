//! The lidar crate's integration tests, in one binary so that CI links it once.

mod common;

mod bad_settings;
mod determinism;
mod limits;
mod plane;
mod ply_output;
mod rings;
mod street;
mod terrestrial;
