//! The fidelity crate's integration tests, in one binary so that CI links it once.

mod hand_made_frames;
mod paraboloid_cap;
