//! The render crate's integration tests, in one binary so that CI links it once.

mod map_casters;
