//! The cli crate's integration tests, in one binary so that CI links it once.

mod common;

mod architecture_table;
mod autzen_scene;
mod bad_input;
mod bare_points_render;
mod classification_render;
mod columns_flag;
mod compare_command;
mod geo_offset;
mod geometry_checks;
mod intensity_material;
mod large_coordinates;
mod leftovers;
mod outputs_spare_inputs;
mod path_integrator_flags;
mod peer_files;
mod prep_robustness_flags;
mod resimulation_backends;
mod sample_parts;
mod scan_command;
mod scan_measures;
mod scene_prep_keys;
mod size_limits;
mod store_info;
mod streamed_prep;
mod sweep_map;
