//! The vulkan crate's integration tests, in one binary so that CI links it once. Those that
//! need prep (points prepped into patches, scene files loaded) are pointray-render's, so that
//! this crate does not depend on pointray-surface, even for its tests.

mod bad_geometry;
mod bench_hooks;
mod common;
mod devices;
mod hit_reordering;
mod layouts;
mod path_tracing;
mod reflection;
mod shadow;
mod sphere_normals;
mod trace_target;
