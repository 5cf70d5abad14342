//! The cpu crate's integration tests, in one binary so that CI links it once. Those that need
//! prep (points prepped into patches, scene files loaded) are pointray-render's, so that this
//! crate does not depend on pointray-surface, even for its tests.

mod bad_input;
mod camera_and_light_updates;
mod common;
mod first_hit;
mod plane_and_sphere;
mod shadows_and_reflections;
