//! Timing one scene at one setting: prepare (build), warm up, time the frame loop, count
//! the rays and the intersection-shader calls.

use std::time::{Duration, Instant};

use pointray_scene::{RenderSettings, Scene};
use pointray_vulkan::{
    BuildReport, PixelOutput, PreparedScene, RayCounts, SceneLayout, VulkanError, VulkanRenderer,
};

use crate::stats::{median, p90};

/// How many frames to warm up with and how many to time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameCounts {
    pub warmup: u32,
    pub timed: u32,
}

/// Warm-up goes on in rounds of `warmup` frames until at least this long has passed. On the
/// H200, after 50 warm-up frames (0.05 s), the first case of the 1,195K model, timed right
/// after the other models' cases, ran slow in three suite runs of five (a tenth of its frames
/// at 2.4 ms instead of 0.95, or all of them 50% slow) with the SM clock steady at its
/// maximum; timed alone it did not. With this warm-up, two suite runs in a row were clean
/// (bench/RESULTS.md, runs 5 and 6).
pub const MIN_WARMUP: Duration = Duration::from_millis(500);

/// What one timed case measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    pub trace_median: Duration,
    pub trace_p90: Duration,
    pub frame_median: Duration,
    pub frame_p90: Duration,
    /// Host wall time of the timed loop divided by its frames.
    pub wall_per_frame: Duration,
    /// Every ray and every patch intersection-shader call of one frame, counted on the GPU.
    pub counts: RayCounts,
    pub build: BuildReport,
}

pub fn measure(
    renderer: &VulkanRenderer,
    scene: &Scene,
    settings: &RenderSettings,
    layout: SceneLayout,
    output: PixelOutput,
    frames: FrameCounts,
) -> Result<Measurement, VulkanError> {
    measure_prepared(renderer, &renderer.prepare_with_layout(scene, layout)?, settings, output, frames)
}

/// As `measure`, on a scene already on the GPU (prepared for `settings`' buffers).
pub fn measure_prepared(
    renderer: &VulkanRenderer,
    prepared: &PreparedScene,
    settings: &RenderSettings,
    output: PixelOutput,
    frames: FrameCounts,
) -> Result<Measurement, VulkanError> {
    if frames.warmup > 0 {
        let start = Instant::now();
        loop {
            renderer.trace_frames(prepared, settings, frames.warmup, output)?;
            if start.elapsed() >= MIN_WARMUP {
                break;
            }
        }
    }
    let times = renderer.trace_frames(prepared, settings, frames.timed, output)?;
    Ok(Measurement {
        trace_median: median(&times.trace),
        trace_p90: p90(&times.trace),
        frame_median: median(&times.frame),
        frame_p90: p90(&times.frame),
        wall_per_frame: times.wall / frames.timed,
        counts: renderer.count_rays(prepared, settings)?,
        build: prepared.build_report(),
    })
}
