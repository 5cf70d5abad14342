//! The cpu crate's integration tests, in one binary so that CI links it once.

mod bad_input;
mod camera_and_light_updates;
mod common;
mod compact_store_image;
mod first_hit;
mod hostile_coordinates;
mod light_leaks;
mod path_tracing;
mod plane_and_sphere;
mod point_colors;
mod shadows_and_reflections;
mod tiles;
