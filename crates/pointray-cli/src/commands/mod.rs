//! One module per subcommand.

pub mod bench;
pub mod cache;
pub mod compare;
pub mod consistency;
pub mod devices;
pub mod fidelity;
pub mod info;
pub mod prep;
pub mod render;
pub mod resimulation;
pub mod sample;
pub mod scan;
pub mod view;
