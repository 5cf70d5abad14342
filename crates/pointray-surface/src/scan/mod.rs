//! Scan-aware patches (METHOD.md §2.8): where a LiDAR scan's sensor is known and its lines
//! can be found, the patches are shaped by the line structure instead of by the nearest
//! points alone. It holds the scan lines (`lines`, `noise`), the neighbourhoods along and
//! across them (`neighborhood`, `plane_vote`, `levels`), the edges and free space the sensor
//! saw (`edges`, `free_space`), the shaped patches (`patches`, `normal_smoothing`) and the
//! stage `prep` calls (`prep`).
//!
//! It may use the core pipeline at the crate root (normals, radii, the fit, the report and
//! progress), `pointray-patches` (the settings), `pointray-kernels` and `pointray-io`; it
//! does not use `tiles`.

pub mod edges;
mod free_space;
mod levels;
pub mod lines;
pub mod neighborhood;
mod noise;
mod normal_smoothing;
pub mod patches;
mod plane_vote;
pub(crate) mod prep;
