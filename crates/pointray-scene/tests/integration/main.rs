//! The scene crate's integration tests, in one binary so that CI links it once.

mod color_sources;
mod common;
mod fuzz_regressions;
mod image_output;
mod loading;
mod path_tracing_settings;
mod point_set_cache;
mod procedural;
mod scene_file_parsing;
