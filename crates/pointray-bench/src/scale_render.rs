//! The renderer the scale suite times: the Vulkan backend (GPU timestamps, as the other
//! suites) or the CPU backend (the wall time of whole frames).

use std::time::{Duration, Instant};

use pointray_cpu::CpuRenderer;
use pointray_scene::{RenderSettings, Scene};
use pointray_vulkan::{PixelOutput, PreparedScene, VulkanRenderer};

use crate::error::BenchError;
use crate::measure::{FrameCounts, measure_prepared};
use crate::scale_fit::DeviceLimits;
use crate::stats::median;

/// The CPU backend times frames until this much time has passed (at least one frame, at
/// most the timed count): a frame of a large scene takes seconds there.
const CPU_TIMING_BUDGET: Duration = Duration::from_secs(3);

#[derive(Clone, Copy)]
pub enum ScaleBackend<'a> {
    Vulkan(&'a VulkanRenderer),
    Cpu,
}

/// A scene ready to trace, with the backend that prepared it.
pub enum ReadyScene<'a> {
    Vulkan { renderer: &'a VulkanRenderer, prepared: Box<PreparedScene> },
    Cpu(Box<CpuRenderer>),
}

/// What making a scene ready cost.
pub struct BuildCosts {
    /// The bottom-level build (GPU BLAS, or the CPU renderer's BVHs).
    pub blas: Duration,
    /// Everything the scene holds on the GPU; `None` on the CPU backend.
    pub gpu_bytes: Option<u64>,
    /// Bottom levels: one per mesh and per tile of a point set.
    pub tiles: usize,
}

impl<'a> ScaleBackend<'a> {
    pub fn describe(&self) -> String {
        match self {
            Self::Vulkan(renderer) => format!("vulkan, {}", renderer.device_info()),
            Self::Cpu => format!("cpu, {} threads", rayon::current_num_threads()),
        }
    }

    /// How frames are timed, for the report.
    pub fn timing(&self) -> &'static str {
        match self {
            Self::Vulkan(_) => {
                "FPS = 1 / median GPU time of a whole frame (trace and copy-out of the display colour)."
            }
            Self::Cpu => "FPS = 1 / median wall time of a whole frame (at least one, for up to 3 s).",
        }
    }

    pub fn device_limits(&self) -> Option<DeviceLimits> {
        match self {
            Self::Vulkan(renderer) => Some(DeviceLimits::from(renderer.device_info())),
            Self::Cpu => None,
        }
    }

    /// Uploads and builds `scene` (Vulkan) or builds its BVHs (CPU). `case` names it in errors.
    pub fn prepare(&self, scene: &Scene, case: &str) -> Result<(ReadyScene<'a>, BuildCosts), BenchError> {
        match *self {
            Self::Vulkan(renderer) => {
                let prepared = renderer
                    .prepare(scene)
                    .map_err(|source| BenchError::Vulkan { case: case.to_string(), source })?;
                let report = prepared.build_report();
                let costs = BuildCosts {
                    blas: report.blas_build,
                    gpu_bytes: Some(report.gpu_bytes()),
                    tiles: report.blas_count,
                };
                Ok((ReadyScene::Vulkan { renderer, prepared: Box::new(prepared) }, costs))
            }
            Self::Cpu => {
                let started = Instant::now();
                let renderer = CpuRenderer::new(scene);
                let costs =
                    BuildCosts { blas: started.elapsed(), gpu_bytes: None, tiles: renderer.tile_count() };
                Ok((ReadyScene::Cpu(Box::new(renderer)), costs))
            }
        }
    }
}

impl ReadyScene<'_> {
    /// The median time of one whole frame with `settings`; `case` names it in errors.
    pub fn frame_time(
        &self,
        settings: &RenderSettings,
        frames: FrameCounts,
        case: &str,
    ) -> Result<Duration, BenchError> {
        match self {
            Self::Vulkan { renderer, prepared } => {
                measure_prepared(renderer, prepared, settings, PixelOutput::Display, frames)
                    .map(|measured| measured.frame_median)
                    .map_err(|source| BenchError::Vulkan { case: case.to_string(), source })
            }
            Self::Cpu(renderer) => Ok(cpu_frame_time(renderer, settings, frames)),
        }
    }
}

fn cpu_frame_time(renderer: &CpuRenderer, settings: &RenderSettings, frames: FrameCounts) -> Duration {
    for _ in 0..frames.warmup.min(1) {
        renderer.render(settings);
    }
    let started = Instant::now();
    let mut times = Vec::new();
    while times.is_empty() || (times.len() < frames.timed as usize && started.elapsed() < CPU_TIMING_BUDGET) {
        let frame_started = Instant::now();
        renderer.render(settings);
        times.push(frame_started.elapsed());
    }
    median(&times)
}
