//! The io crate's integration tests, in one binary so that CI links it once.

mod atomic_write;
mod common;
mod dispatch;
mod file_roles;
mod formats_copc;
mod formats_detect;
mod formats_e57;
mod formats_fuzz_regressions;
mod formats_las;
mod formats_pcd;
mod formats_raw_bin;
mod formats_xyz;
mod image_output;
mod obj;
mod peer_files;
mod ply_attributes;
mod ply_bad_input;
mod ply_round_trip;
mod ply_shared_data;
mod point_stream;
mod real_sweeps;
