//! What the shaping stages of `prep` hand to the boxes, the cold records and the report.

use pointray_kernels::PatchHot;
use rayon::prelude::*;

use crate::density_radius::RadiusAdjustments;
use crate::prep_report::{FitCounts, RadiusFallbacks, ScanSummary};
use crate::quadratic_fit::FitKind;

/// The patches' shapes (frames, supports and fits), and what the report says of them.
pub(crate) struct ShapedPatches {
    pub(crate) hot: Vec<PatchHot>,
    pub(crate) fits: FitCounts,
    /// The radius each point's colour reach is scaled from (`gather_cold`).
    pub(crate) color_radii: Vec<f32>,
    pub(crate) radius_fallbacks: RadiusFallbacks,
    pub(crate) radius_adjustments: RadiusAdjustments,
    pub(crate) replaced_input_normals: usize,
    pub(crate) scan: Option<ScanSummary>,
}

/// How many fits of each kind.
pub(crate) fn count_fits(kinds: &[FitKind]) -> FitCounts {
    let count = |wanted| kinds.par_iter().filter(|&&kind| kind == wanted).count();
    FitCounts {
        quadratic: count(FitKind::Quadratic),
        plane: count(FitKind::Plane),
        flat: count(FitKind::Flat),
    }
}
