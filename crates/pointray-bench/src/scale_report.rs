//! The scale suite's results: one row per rung, measured or skipped with its reason, as JSON
//! and as a markdown table.

use std::fmt::Write as _;

use pointray_scene::HotRecords;
use serde::Serialize;

/// One rung: what it measured, or why it was skipped.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScaleRow {
    pub label: String,
    pub points: u64,
    /// How the points were made (a stand-in sampled on a mesh).
    pub stand_in: String,
    #[serde(flatten)]
    pub outcome: RungOutcome,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "outcome")]
pub enum RungOutcome {
    Measured(RungMeasurement),
    Skipped { reason: String },
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RungMeasurement {
    /// How prep ran: "in memory", or "streamed" in tiles when a single pass would not fit
    /// the budget (`pointray prep`'s rule).
    pub prep_route: String,
    /// Reading the points file (streamed prep reads it in its own stages: 0).
    pub read_seconds: f64,
    /// `prep` itself (streamed: reading and writing the store included).
    pub prep_seconds: f64,
    pub prep_points_per_second: f64,
    /// The process's peak resident memory while `prep` ran (the read points included).
    pub prep_peak_rss_bytes: Option<u64>,
    pub store_bytes: u64,
    /// Writing the store (streamed prep writes it in its own last stage: 0).
    pub store_write_seconds: f64,
    /// Reading the store and making the scene ready to trace (upload and BLAS, or the CPU BVH).
    pub load_seconds: f64,
    /// Building the bottom level(s): GPU BLAS, or the CPU renderer's BVHs.
    pub blas_build_seconds: f64,
    /// Bottom levels built: one per tile of the points (`maxPrimitiveCount` patches at
    /// most on the GPU) and one for the floor.
    pub bottom_levels: usize,
    /// Consecutive patches one box of those bottom levels bounds.
    pub patches_per_box: u32,
    /// The form of the points' hot records on the GPU; `None` on the CPU backend.
    pub hot_records: Option<HotRecords>,
    /// Everything the scene keeps on the GPU, per patch; `None` on the CPU backend.
    pub gpu_bytes_per_point: Option<f64>,
    /// The most the scene held on the GPU at once while it was built, per patch.
    pub gpu_build_peak_bytes_per_point: Option<f64>,
    /// Frames per second by size, with shadows and one reflection bounce.
    pub fps: Vec<SizeFps>,
    /// The PSNR of a small frame of this rung against the first measured rung's, in dB;
    /// `None` for that rung. Every rung samples the same mesh, so a low figure says the frames
    /// misrender: records read from the wrong place once made most of a 300M set vanish (20.9
    /// dB at 1920x1080 against 30M points, where a right frame gives about 40).
    pub image_psnr_db: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SizeFps {
    pub width: u32,
    pub height: u32,
    pub fps: f64,
    pub frame_ms: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScaleReport {
    /// The backend and device that rendered.
    pub backend: String,
    /// How each frame was timed.
    pub timing: String,
    pub rows: Vec<ScaleRow>,
}

impl ScaleRow {
    /// One line for the terminal as the rung completes.
    pub fn summary(&self) -> String {
        match &self.outcome {
            RungOutcome::Skipped { reason } => format!("{}: skipped, {reason}", self.label),
            RungOutcome::Measured(m) => {
                let fps: Vec<String> =
                    m.fps.iter().map(|s| format!("{:.1} FPS at {}x{}", s.fps, s.width, s.height)).collect();
                format!(
                    "{}: prep {} {:.2} s ({:.2} M points/s, peak {}), store {:.1} MB, load {:.2} s, BLAS {:.2} s ({} bottom levels, {} patches a box{}), GPU {}, {}{}",
                    self.label,
                    m.prep_route,
                    m.prep_seconds,
                    m.prep_points_per_second / 1e6,
                    m.prep_peak_rss_bytes.map_or("unknown".into(), |b| format!("{:.2} GB", b as f64 / 1e9)),
                    m.store_bytes as f64 / 1e6,
                    m.load_seconds,
                    m.blas_build_seconds,
                    m.bottom_levels,
                    m.patches_per_box,
                    m.hot_records.map_or(String::new(), |form| format!(", {} hot records", form.name())),
                    m.gpu_bytes_per_point.map_or("n/a".into(), |b| format!("{b:.0} B/point")),
                    fps.join(", "),
                    m.image_psnr_db
                        .map_or(String::new(), |db| format!(", image {db:.1} dB against the first rung's"))
                )
            }
        }
    }
}

/// The report as a markdown table, one row per rung.
pub fn scale_markdown(report: &ScaleReport) -> String {
    let mut text = format!("Backend: {}. {}\n\n", report.backend, report.timing);
    let sizes: Vec<(u32, u32)> = report
        .rows
        .iter()
        .find_map(|row| match &row.outcome {
            RungOutcome::Measured(m) => Some(m.fps.iter().map(|s| (s.width, s.height)).collect()),
            RungOutcome::Skipped { .. } => None,
        })
        .unwrap_or_default();
    let size_columns: String = sizes.iter().map(|(w, h)| format!(" FPS {w}x{h} |")).collect();
    let _ = writeln!(
        text,
        "| points | prep s | M points/s | prep peak RSS GB (B/point) | store GB | GPU B/point | GPU peak B/point while building | load s | BLAS build s | bottom levels | image dB against the first rung |{size_columns}"
    );
    let _ = writeln!(
        text,
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|{}",
        "---:|".repeat(sizes.len())
    );
    for row in &report.rows {
        let _ = writeln!(text, "{}", table_row(row, sizes.len()));
    }
    if let Some(stand_in) = report.rows.first().map(|row| &row.stand_in) {
        let _ = writeln!(text, "\nPoints: {stand_in}.");
    }
    text
}

fn table_row(row: &ScaleRow, size_count: usize) -> String {
    let m = match &row.outcome {
        RungOutcome::Skipped { reason } => {
            return format!("| {} | skipped: {reason} |{}", row.label, " |".repeat(9 + size_count));
        }
        RungOutcome::Measured(m) => m,
    };
    let peak = m.prep_peak_rss_bytes.map_or("–".into(), |bytes| {
        format!("{:.2} ({:.0})", bytes as f64 / 1e9, bytes as f64 / row.points.max(1) as f64)
    });
    let fps: String = m.fps.iter().map(|s| format!(" {:.1} |", s.fps)).collect();
    format!(
        "| {} | {:.2} | {:.2} | {peak} | {:.2} | {} | {} | {:.2} | {:.2} | {} | {} |{fps}",
        row.label,
        m.prep_seconds,
        m.prep_points_per_second / 1e6,
        m.store_bytes as f64 / 1e9,
        m.gpu_bytes_per_point.map_or("–".into(), |b| format!("{b:.0}")),
        m.gpu_build_peak_bytes_per_point.map_or("–".into(), |b| format!("{b:.0}")),
        m.load_seconds,
        m.blas_build_seconds,
        m.bottom_levels,
        m.image_psnr_db.map_or("–".into(), |db| format!("{db:.1}")),
    )
}
