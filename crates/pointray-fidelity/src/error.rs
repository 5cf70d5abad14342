//! What can go wrong while measuring fidelity.

use std::path::PathBuf;

use glam::Vec3;

use crate::RenderError;
use crate::range_tolerance::RangeTolerance;

#[derive(Debug, thiserror::Error)]
pub enum FidelityError {
    #[error("fidelity needs at least {minimum} views, got {requested}")]
    TooFewViews { requested: usize, minimum: usize },
    #[error("writing {path}: {source}")]
    Image { path: std::path::PathBuf, source: pointray_io::IoError },
    #[error("no views to render")]
    NoViews,
    #[error(
        "unknown view `{text}`: expected a number of views around the mesh (6 or more), `sensor`, \
         `sensor:YAWS`, `above` or `above:HEIGHT`"
    )]
    UnknownView { text: String },
    #[error("view {view}: {reason}")]
    InvalidView { view: String, reason: String },
    #[error("the image size must be 1 to {maximum} pixels, got {size}")]
    ImageSize { size: u32, maximum: u32 },
    #[error("the field of view must lie between 0 and 170 degrees, got {0}")]
    InvalidFov(f32),
    #[error("the up axis must be a finite, non-zero vector, got {0}")]
    InvalidUp(Vec3),
    #[error(
        "the points carry no sensor position (no sensor origins, no viewpoint): give one, e.g. \
         `--sensor x,y,z`"
    )]
    NoSensor,
    #[error("the sensor position is not finite")]
    NonFiniteSensor,
    #[error("the points carry {origins} sensor origins for {points} points")]
    SensorOriginCount { origins: usize, points: usize },
    #[error(
        "seen from the sensor, the returns span no band of elevations: sensor views need at least two beams"
    )]
    NoElevationBand,
    #[error(
        "the range tolerance needs finite, non-negative terms, not all zero: absolute {}, range \
         fraction {}, spacing multiple {}", .0.absolute, .0.range_fraction, .0.spacing_multiple
    )]
    InvalidTolerance(RangeTolerance),
    #[error("{0} points are more than a neighbour search can index")]
    TooManyPoints(usize),
    #[error("the ray budget must be at least 1")]
    NoRays,
    #[error("the points carry no ring indices: the beam spacing needs each point's ring")]
    NoRings,
    #[error("the points carry {rings} ring indices for {points} points")]
    RingCount { rings: usize, points: usize },
    #[error("the points lie on {0} ring(s) seen from the sensor: beam spacing needs two or more")]
    TooFewRings(usize),
    #[error("{sources} patch sources for {patches} patches")]
    PatchSourceCount { sources: usize, patches: usize },
    #[error("patch source {source_index} is past the {points} points")]
    PatchSourceOutOfRange { source_index: usize, points: usize },
    #[error("the mesh has no triangles (or no vertices): nothing to compare against")]
    EmptyMesh,
    #[error("the point set has no patches: nothing to compare")]
    EmptyPatchSet,
    #[error("images differ in size: mesh {mesh_width}x{mesh_height}, points {points_width}x{points_height}")]
    ImageSizeMismatch { mesh_width: u32, mesh_height: u32, points_width: u32, points_height: u32 },
    #[error("the renderer reported triangle {triangle} of a mesh of {triangles}")]
    TriangleOutOfRange { triangle: u32, triangles: usize },
    #[error("rendering the {what} for view {view} failed: {source}")]
    Render { what: &'static str, view: usize, source: RenderError },
    #[error("{path}: cannot write the fidelity report: {source}")]
    Write { path: PathBuf, source: pointray_io::IoError },
}
