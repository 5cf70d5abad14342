//! One row of a benchmark report, in units people read (ms, FPS, rays/s, MiB).

use serde::Serialize;

use crate::measure::Measurement;

/// What was timed in a case besides the default point set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Variant {
    /// The point set with our defaults: cell radii, one geometry, split buffers, tight boxes,
    /// the disk test, display output.
    Points,
    /// The model's triangle mesh in place of its points (the limit).
    Mesh,
    /// The paper's configuration: its radius, cube boxes and the box test.
    PaperConfiguration,
    /// Ablation: one BLAS geometry per patch box.
    GeometryPerAabb,
    /// Ablation: hot and cold records in one buffer.
    CombinedBuffers,
    /// Ablation: the paper's cubes instead of tight boxes.
    CubeBoxes,
    /// Ablation: the paper's box test instead of the disk test.
    BoxAcceptance,
    /// Ablation: hot records packed (32 bytes a patch) and decoded on every intersection
    /// call, as a scene takes them where unpacked ones do not fit.
    PackedRecords,
    /// Ablation: every pixel's AOV record (48 bytes) copied out instead of its display colour.
    AovOutput,
    /// Ablation: shader execution reordering of every path segment.
    HitReordering,
    /// Ablation: k = 6 neighbours instead of 9, so smaller, less overlapping patches.
    SixNeighbours,
    /// Ablation: patches reaching 0.7 of the paper's support radius (`PrepSettings::disk_scale`).
    SmallerDisks,
    /// Ablation: the paper's support radius instead of the cell radius (`RadiusMode::Paper`).
    PaperRadius,
    /// Ablation: each patch as two triangles traced as a mesh, its quadratic not solved
    /// (`triangle_proxies`): a bound from below on a layout of triangle proxies.
    TriangleProxies,
}

impl Variant {
    pub fn label(self) -> &'static str {
        match self {
            Self::Points => "points",
            Self::Mesh => "mesh",
            Self::PaperConfiguration => "paper's configuration (its radius, cube boxes, box test)",
            Self::GeometryPerAabb => "one geometry per AABB",
            Self::CombinedBuffers => "combined buffers",
            Self::CubeBoxes => "cube boxes",
            Self::BoxAcceptance => "box acceptance",
            Self::PackedRecords => "packed hot records",
            Self::AovOutput => "AOV output",
            Self::HitReordering => "hit reordering (SER)",
            Self::SixNeighbours => "k = 6 neighbours",
            Self::SmallerDisks => "disk scale 0.7",
            Self::PaperRadius => "paper's radius",
            Self::TriangleProxies => "triangle proxies (unrefined)",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CaseResult {
    pub model: String,
    /// How the model was made when it is a stand-in; `None` for exact data.
    pub stand_in: Option<String>,
    pub variant: Variant,
    /// Patches or triangles of the model.
    pub primitives: usize,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub trace_median_ms: f64,
    pub trace_p90_ms: f64,
    pub frame_median_ms: f64,
    pub frame_p90_ms: f64,
    pub wall_ms_per_frame: f64,
    /// 1000 / frame_median_ms (GPU time of a whole frame, copy-out included).
    pub fps: f64,
    pub rays_per_frame: u64,
    /// rays_per_frame / trace_median.
    pub rays_per_second: f64,
    pub intersection_calls_per_frame: u64,
    /// intersection_calls_per_frame / rays_per_frame: patch boxes each ray's traversal
    /// reported to the intersection shader (0 for meshes, which have none).
    pub intersection_calls_per_ray: f64,
    pub blas_build_ms: f64,
    pub tlas_build_ms: f64,
    pub blas_bytes: u64,
    pub tlas_bytes: u64,
    pub geometry_bytes: u64,
    pub paper_fps: Option<f64>,
    /// fps / paper_fps.
    pub ratio_to_paper: Option<f64>,
}

/// Who and what a measurement was of.
pub struct CaseLabel<'a> {
    pub model: &'a str,
    pub stand_in: Option<String>,
    pub variant: Variant,
    pub primitives: usize,
    pub paper_fps: Option<f64>,
}

impl CaseResult {
    pub fn new(label: CaseLabel, width: u32, height: u32, frames: u32, m: &Measurement) -> Self {
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let fps = if m.frame_median.is_zero() { 0.0 } else { 1.0 / m.frame_median.as_secs_f64() };
        let rays_per_second =
            if m.trace_median.is_zero() { 0.0 } else { m.counts.rays as f64 / m.trace_median.as_secs_f64() };
        Self {
            model: label.model.to_string(),
            stand_in: label.stand_in,
            variant: label.variant,
            primitives: label.primitives,
            width,
            height,
            frames,
            trace_median_ms: ms(m.trace_median),
            trace_p90_ms: ms(m.trace_p90),
            frame_median_ms: ms(m.frame_median),
            frame_p90_ms: ms(m.frame_p90),
            wall_ms_per_frame: ms(m.wall_per_frame),
            fps,
            rays_per_frame: m.counts.rays,
            rays_per_second,
            intersection_calls_per_frame: m.counts.intersection_calls,
            intersection_calls_per_ray: m.counts.intersection_calls_per_ray(),
            blas_build_ms: ms(m.build.blas_build),
            tlas_build_ms: ms(m.build.tlas_build),
            blas_bytes: m.build.blas_bytes,
            tlas_bytes: m.build.tlas_bytes,
            geometry_bytes: m.build.geometry_bytes,
            paper_fps: label.paper_fps,
            ratio_to_paper: label.paper_fps.map(|paper| fps / paper),
        }
    }
}
