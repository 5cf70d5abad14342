//! The renderer the scale suite times: the Vulkan backend (GPU timestamps, as the other
//! suites) or the CPU backend (the wall time of whole frames).

use std::time::{Duration, Instant};

use pointray_cpu::CpuRenderer;
use pointray_render::{Backend, BackendError, ReadyScene, Tracer};
use pointray_scene::{HotRecords, RenderSettings, RenderedImage, Scene};
use pointray_vulkan::{PixelOutput, VulkanError};

use crate::error::BenchError;
use crate::measure::{FrameCounts, measure_prepared};
use crate::scale_fit::DeviceLimits;
use crate::stats::median;

/// The CPU backend times frames until this much time has passed (at least one frame, at
/// most the timed count): a frame of a large scene takes seconds there.
const CPU_TIMING_BUDGET: Duration = Duration::from_secs(3);

/// The backend the suite renders with, and what it says of it.
#[derive(Clone, Copy)]
pub struct ScaleBackend<'a>(pub &'a Backend);

/// What making a scene ready cost.
pub struct BuildCosts {
    /// The bottom-level build (GPU BLAS, or the CPU renderer's BVHs).
    pub blas: Duration,
    /// Everything the scene holds on the GPU; `None` on the CPU backend.
    pub gpu_bytes: Option<u64>,
    /// The most it held at once while it was built; `None` on the CPU backend.
    pub gpu_peak_bytes: Option<u64>,
    /// Bottom levels: one per mesh and per tile of a point set.
    pub tiles: usize,
    /// Consecutive patches one box of the GPU's bottom levels bounds; 1 on the CPU backend.
    pub patches_per_box: u32,
    /// The form of the point sets' hot records on the GPU; `None` on the CPU backend.
    pub hot_records: Option<HotRecords>,
}

impl ScaleBackend<'_> {
    pub fn describe(&self) -> String {
        match self.0 {
            Backend::Vulkan(renderer) => format!("vulkan, {}", renderer.device_info()),
            Backend::Cpu => format!("cpu, {} threads", rayon::current_num_threads()),
        }
    }

    /// How frames are timed, for the report.
    pub fn timing(&self) -> &'static str {
        match self.0 {
            Backend::Vulkan(_) => {
                "FPS = 1 / median GPU time of a whole frame (trace and copy-out of the display colour)."
            }
            Backend::Cpu => "FPS = 1 / median wall time of a whole frame (at least one, for up to 3 s).",
        }
    }

    pub fn device_limits(&self) -> Option<DeviceLimits> {
        match self.0 {
            Backend::Vulkan(renderer) => Some(DeviceLimits::from(renderer.device_info())),
            Backend::Cpu => None,
        }
    }

    /// Uploads and builds `scene` for frames with `settings` (Vulkan) or builds its BVHs
    /// (CPU). `case` names it in errors.
    pub fn prepare(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        case: &str,
    ) -> Result<(ReadyScene, BuildCosts), BenchError> {
        let started = Instant::now();
        let ready = self.0.prepare(scene, settings).map_err(|source| backend_error(case, source))?;
        let costs = match &ready {
            ReadyScene::Vulkan(prepared) => {
                let report = prepared.build_report();
                BuildCosts {
                    blas: report.blas_build,
                    gpu_bytes: Some(report.gpu_bytes()),
                    gpu_peak_bytes: Some(report.peak_build_bytes),
                    tiles: report.blas_count,
                    patches_per_box: report.patches_per_box,
                    hot_records: Some(report.hot_records),
                }
            }
            ReadyScene::Cpu(renderer) => BuildCosts {
                blas: started.elapsed(),
                gpu_bytes: None,
                gpu_peak_bytes: None,
                tiles: renderer.tile_count(),
                patches_per_box: 1,
                hot_records: None,
            },
        };
        Ok((ready, costs))
    }

    /// Where `ready`'s point sets stream, loads the tiles its camera needs for frames of
    /// `settings`' size and says how many are on the GPU.
    pub fn stream_tiles(
        &self,
        ready: &mut ReadyScene,
        settings: &RenderSettings,
        case: &str,
    ) -> Result<(), BenchError> {
        if let Some(tiles) = ready.stream_tiles(settings).map_err(|source| backend_error(case, source))? {
            println!(
                "{case}: {} of {} tiles on the GPU in full and {} coarse ({:.2} GB), {} in full and {} coarse of the \
                 {} in view",
                tiles.resident,
                tiles.tiles,
                tiles.coarse,
                tiles.resident_bytes as f64 / 1e9,
                tiles.in_view_resident,
                tiles.in_view_coarse,
                tiles.in_view
            );
        }
        Ok(())
    }

    /// The median time of one whole frame of `ready` with `settings`; `case` names it in
    /// errors.
    pub fn frame_time(
        &self,
        ready: &ReadyScene,
        settings: &RenderSettings,
        frames: FrameCounts,
        case: &str,
    ) -> Result<Duration, BenchError> {
        match self.0.tracer(ready).map_err(|source| backend_error(case, source))? {
            Tracer::Vulkan(renderer, prepared) => {
                measure_prepared(renderer, prepared, settings, PixelOutput::Display, frames)
                    .map(|measured| measured.frame_median)
                    .map_err(|source| vulkan_error(case, source))
            }
            Tracer::Cpu(renderer) => Ok(cpu_frame_time(renderer, settings, frames)),
        }
    }

    /// One frame of `ready` with `settings`, to compare with another rung's.
    pub fn image(
        &self,
        ready: &ReadyScene,
        settings: &RenderSettings,
        case: &str,
    ) -> Result<RenderedImage, BenchError> {
        self.0.trace(ready, settings).map_err(|source| backend_error(case, source))
    }
}

fn vulkan_error(case: &str, source: VulkanError) -> BenchError {
    BenchError::Vulkan { case: case.to_string(), source }
}

fn backend_error(case: &str, source: BackendError) -> BenchError {
    BenchError::Backend { case: case.to_string(), source }
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
