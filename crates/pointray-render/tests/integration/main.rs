//! The render crate's integration tests, in one binary so that CI links it once. The
//! renderers' tests that need prep (points prepped into patches, scene files loaded, the demo)
//! live here too, in `cpu` and `vulkan`, so that pointray-cpu and pointray-vulkan do not depend
//! on pointray-surface, even for their tests.

mod coarse_tiles;
mod cpu;
mod map_casters;
mod vulkan;
