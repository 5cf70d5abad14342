//! A LiDAR simulator: a sensor's rays cast into a scene of meshes (and point sets) with the
//! CPU renderer's BVHs, each first hit recorded as a return with its intensity, ring,
//! azimuth, time, class and sensor origin, as real spinning and terrestrial scanners record
//! them.
//!
//! - `sensor.rs`, `presets.rs`: the ray grid of a sensor (rings × azimuth columns), its
//!   ranges, noise and dropout; the Velodyne HDL-64E, HDL-32E and VLP-16, the Ouster OS1-128
//!   and a terrestrial scanner with their published angles.
//! - `pose.rs`: stations (position and yaw) and the scene's up axis.
//! - `lidar_scene.rs`, `surface.rs`, `classification.rs`: what is scanned, how bright and of
//!   which ASPRS class each object's returns are.
//! - `street.rs`: a procedural street, the ground truth for `pointray fidelity`.
//! - `scan.rs`: the casting, deterministic for a seed; `returns.rs`: what it records;
//!   `ply_output.rs`: the points file.
//! - `resimulation.rs`, `range_agreement.rs`: a real sweep's rays cast from a pose into a
//!   prepped map (by any `MapCaster`: the CPU's here, a GPU's in pointray-render), and the
//!   ranges met scored against those the sensor measured; `caster_agreement.rs`: two
//!   casters' ranges for the same rays set against each other.
//!
//! Positions are in the scene's coordinates: Z up for the street (as KITTI and nuScenes frames are),
//! Y up for pointray scene files.

pub mod caster_agreement;
pub mod classification;
pub mod error;
pub mod lidar_scene;
pub mod ply_output;
pub mod pose;
pub mod presets;
pub mod range_agreement;
pub mod resimulation;
pub mod returns;
pub mod scan;
pub mod sensor;
pub mod street;
pub mod surface;

pub use caster_agreement::CasterAgreement;
pub use classification::Classification;
pub use error::LidarError;
pub use lidar_scene::{LidarScene, map_scene};
pub use pose::{SensorPose, UpAxis};
pub use presets::SensorPreset;
pub use range_agreement::RangeAgreement;
pub use resimulation::{
    MapCaster, SENSOR_ACCEPTANCE, SweepRays, pose_about, resimulate, resimulate_from, sensor_rays,
};
pub use returns::{Return, ScanStats, to_point_cloud};
pub use scan::{NoProgress, Scan, ScanProgress, scan};
pub use sensor::{Elevations, Sensor};
pub use surface::{Surface, merged_mesh};
