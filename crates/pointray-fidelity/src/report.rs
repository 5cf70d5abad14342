//! What one fidelity run reports.

use std::path::PathBuf;

use pointray_io::TriangleMesh;
use pointray_surface::PatchSet;
use serde::Serialize;

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
    pub size: u32,
    pub patches: usize,
    pub triangles: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewReport {
    /// From the model's centre toward the camera.
    pub direction: [f32; 3],
    pub metrics: FidelityMetrics,
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
            k: patches.params.k,
            acceptance: options.acceptance.name(),
            size: options.size,
            patches: patches.len(),
            triangles: mesh.triangles.len(),
        }
    }
}
