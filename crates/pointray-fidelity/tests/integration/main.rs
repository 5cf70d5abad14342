//! The fidelity crate's integration tests, in one binary so that CI links it once.

mod chosen_views;
mod hand_made_images;
mod paraboloid_cap;
mod real_sweeps;
mod ring_scan;
mod sensor_rays;
mod simulated_street;
mod sphere_normals;
