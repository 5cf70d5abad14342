//! What can go wrong while measuring fidelity.

use std::path::PathBuf;

use crate::RenderError;

#[derive(Debug, thiserror::Error)]
pub enum FidelityError {
    #[error("fidelity needs at least {minimum} views, got {requested}")]
    TooFewViews { requested: usize, minimum: usize },
    #[error("fidelity needs an image size of at least 1 pixel, got {0}")]
    EmptyImage(u32),
    #[error("the mesh has no triangles (or no vertices): nothing to compare against")]
    EmptyMesh,
    #[error("the point set has no patches: nothing to compare")]
    EmptyPatchSet,
    #[error("frames differ in size: mesh {mesh_width}x{mesh_height}, points {points_width}x{points_height}")]
    FrameSizeMismatch { mesh_width: u32, mesh_height: u32, points_width: u32, points_height: u32 },
    #[error("rendering the {what} for view {view} failed: {source}")]
    Render { what: &'static str, view: usize, source: RenderError },
    #[error("{path}: cannot write the fidelity report: {source}")]
    Write { path: PathBuf, source: pointray_io::IoError },
}
