//! What one fidelity run reports.

use std::path::PathBuf;

use pointray_io::TriangleMesh;
use pointray_patches::PatchSet;
use serde::Serialize;

use crate::view_placement::View;
use crate::{FidelityMetrics, FidelityOptions};

/// What was compared, and how.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FidelitySetup {
    /// The input files, when the caller names them.
    pub points_file: Option<PathBuf>,
    pub mesh_file: Option<PathBuf>,
    pub backend: String,
    /// The neighbour count the patches were fitted with.
    pub k: u32,
    pub acceptance: &'static str,
    /// The images' width.
    pub size: u32,
    pub up: [f32; 3],
    /// The lens of explicit and `above` views.
    pub fov_degrees: f32,
    /// What the points' normals are compared against.
    pub mesh_normals: &'static str,
    pub patches: usize,
    pub triangles: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewReport {
    pub label: String,
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub vertical_fov_degrees: f32,
    pub width: u32,
    pub height: u32,
    pub metrics: FidelityMetrics,
}

impl ViewReport {
    pub(crate) fn new(view: View, metrics: FidelityMetrics) -> Self {
        Self {
            label: view.label,
            position: view.camera.position.to_array(),
            look_at: view.camera.look_at.to_array(),
            vertical_fov_degrees: view.camera.vertical_fov_degrees,
            width: view.width,
            height: view.height,
            metrics,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FidelityReport {
    pub setup: FidelitySetup,
    pub views: Vec<ViewReport>,
    /// All views' pixels pooled (not the mean of the per-view numbers).
    pub overall: FidelityMetrics,
    /// Wall-clock time of the renders and comparisons.
    pub seconds: f64,
}

impl FidelitySetup {
    pub(crate) fn describe(
        patches: &PatchSet,
        mesh: &TriangleMesh,
        options: &FidelityOptions,
        backend: String,
    ) -> Self {
        Self {
            points_file: None,
            mesh_file: None,
            backend,
            k: patches.settings.k,
            acceptance: options.acceptance.name(),
            size: options.size,
            up: options.up.to_array(),
            fov_degrees: options.fov_degrees,
            mesh_normals: "angle-weighted vertex normals, interpolated",
            patches: patches.len(),
            triangles: mesh.triangles.len(),
        }
    }
}
