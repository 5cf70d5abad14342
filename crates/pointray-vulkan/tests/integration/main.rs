//! The vulkan crate's integration tests, in one binary so that CI links it once.

mod against_cpu;
mod bad_geometry;
mod bench_hooks;
mod common;
mod demo_scene;
mod devices;
mod hit_reordering;
mod large_coordinates;
mod layouts;
mod path_tracing;
mod point_colors;
mod reflection;
mod shadow;
mod silhouette;
mod sphere_normals;
mod streamed_tiles;
mod tiles;
mod trace_target;
