//! The Vulkan renderer on prepped points and loaded scenes, against the CPU renderer where
//! both draw them. A test skips without a device, and fails without one under `CI=true`.

mod against_cpu;
mod demo_scene;
mod large_coordinates;
mod point_colors;
mod silhouette;
mod streamed_tiles;
mod tiles;
