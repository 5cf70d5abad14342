//! The CPU renderer on prepped points and loaded scenes.

mod compact_store_image;
mod hostile_coordinates;
mod light_leaks;
mod path_tracing;
mod point_colors;
mod tiles;
