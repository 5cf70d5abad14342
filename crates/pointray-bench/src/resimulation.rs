//! The re-simulation benchmark (`bench resim`): the middle sweep of the Ouster OS-1-128
//! sequence (data/scans/real/ouster_os1_128_seq/) re-simulated from its pose, again and again,
//! in a map prepped from the sweeps either side of it, the map uploaded once. Timed per sweep:
//! the GPU time of the cast (timestamps) and the wall time of the whole re-simulation (the
//! sweep's rays and poses uploaded, cast, read back and turned into ranges). Checked: the
//! GPU's ranges against the CPU caster's, and against the ranges the sensor measured.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::DAffine3;
use pointray_io::SweepPoses;
use pointray_lidar::{
    CasterAgreement, LidarScene, MapCaster, RangeAgreement, SweepRays, resimulate, resimulate_from,
};
use pointray_patches::{PatchSet, PrepSettings};
use pointray_render::GpuMapCaster;
use pointray_surface::NoProgress;
use pointray_vulkan::VulkanRenderer;
use serde::Serialize;

use crate::data::data_file;
use crate::error::BenchError;
use crate::measure::FrameCounts;
use crate::stats::{median, p90};

const SEQUENCE: &str = "scans/real/ouster_os1_128_seq";
const MAP_SWEEPS: [&str; 2] = ["scan00.bin", "scan02.bin"];
const CAST_SWEEP: &str = "scan01.bin";
const POSES: &str = "poses_kitti.txt";
/// The re-simulation command's default reach.
const MAX_RANGE_M: f64 = 200.0;
/// Ranges of the two casters closer than this agree (f32 rays, traversals that may take
/// either of two overlapping patches first).
const CASTER_TOLERANCE_M: f64 = 0.01;
const CASE: &str = "bench resim";

pub struct ResimOptions {
    pub data: PathBuf,
    /// Sweeps cast before timing, and sweeps timed.
    pub sweeps: FrameCounts,
}

/// Sweeps cast together, from as many poses in one ray list: one at a time, and a batch, as
/// a sequence's poses would be cast at once.
pub const SWEEPS_PER_CAST: [u32; 2] = [1, 16];

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ResimReport {
    pub device: String,
    /// The sweeps the map was prepped from, and the one cast.
    pub map_sweeps: Vec<String>,
    pub cast_sweep: String,
    pub map_patches: usize,
    pub rays: usize,
    /// Prep of the map, on this machine's cores.
    pub prep_seconds: f64,
    /// The map's upload and acceleration-structure build.
    pub upload_seconds: f64,
    pub throughput: Vec<ThroughputRow>,
    /// One re-simulation of the same sweep on the CPU caster, on this machine's cores.
    pub cpu_sweep_ms: f64,
    /// The GPU's ranges of the sweep cast alone against the CPU caster's.
    pub against_cpu: CasterAgreement,
    pub against_real: RangeAgreement,
}

/// Re-simulations of the sweep from `sweeps_per_cast` poses in one ray list, timed per cast.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ThroughputRow {
    pub sweeps_per_cast: u32,
    pub timed_casts: u32,
    pub gpu_median_ms: f64,
    pub gpu_p90_ms: f64,
    pub wall_median_ms: f64,
    pub wall_p90_ms: f64,
    /// The sweeps of a cast over its median GPU time.
    pub sweeps_per_second_gpu: f64,
    /// The timed sweeps over the wall time of all the casts, one after another.
    pub sweeps_per_second_wall: f64,
    /// Every sweep of a cast met the ranges of the sweep cast alone (the poses are the same).
    pub same_as_alone: bool,
}

/// Preps the map, uploads it to `renderer`'s device once and times the re-simulations.
pub fn run_resimulation(
    renderer: &VulkanRenderer,
    options: &ResimOptions,
) -> Result<ResimReport, BenchError> {
    let file = |name: &str| data_file(&options.data, &Path::new(SEQUENCE).join(name));
    let poses_path = file(POSES)?;
    let poses = SweepPoses::read(&poses_path)?;
    let cast_path = file(CAST_SWEEP)?;
    let pose = poses.for_sweeps(&[cast_path.as_path()], &poses_path)?[0];
    let real = pointray_io::formats::read_point_cloud(&cast_path)?;
    let rays = SweepRays::of_sweep(&real);
    let started = Instant::now();
    let map = std::sync::Arc::new(prepped_map(&options.data, &poses)?);
    let prep_seconds = started.elapsed().as_secs_f64();
    let started = Instant::now();
    let gpu = GpuMapCaster::new(renderer, map.clone()).map_err(backend_error)?;
    let upload_seconds = started.elapsed().as_secs_f64();
    let alone = resimulate(&gpu, &pose, &rays, MAX_RANGE_M).map_err(lidar_error)?;
    let throughput = SWEEPS_PER_CAST
        .iter()
        .map(|&copies| throughput(&gpu, &pose, &rays, &alone, copies, options.sweeps))
        .collect::<Result<_, _>>()?;
    let cpu = LidarScene::from_patches(map.clone()).map_err(lidar_error)?;
    let started = Instant::now();
    let reference = resimulate(&cpu, &pose, &rays, MAX_RANGE_M).map_err(lidar_error)?;
    let cpu_sweep_ms = started.elapsed().as_secs_f64() * 1e3;
    Ok(ResimReport {
        device: renderer.device_info().to_string(),
        map_sweeps: MAP_SWEEPS.iter().map(|name| name.to_string()).collect(),
        cast_sweep: CAST_SWEEP.to_owned(),
        map_patches: map.len(),
        rays: rays.ranges.len(),
        prep_seconds,
        upload_seconds,
        throughput,
        cpu_sweep_ms,
        against_cpu: CasterAgreement::of(&alone, &reference, CASTER_TOLERANCE_M),
        against_real: RangeAgreement::of(&rays, &alone),
    })
}

/// Times casts of `rays` from `copies` copies of `pose` at once: `sweeps` counts sweeps, so
/// each count is divided among the casts (at least one cast each).
fn throughput(
    gpu: &GpuMapCaster,
    pose: &DAffine3,
    rays: &SweepRays,
    alone: &[Option<f64>],
    copies: u32,
    sweeps: FrameCounts,
) -> Result<ThroughputRow, BenchError> {
    let poses = vec![*pose; copies as usize];
    let casts = FrameCounts { warmup: sweeps.warmup.div_ceil(copies), timed: (sweeps.timed / copies).max(1) };
    let (gpu_times, wall_times, wall_total, sweeps_cast) = timed_casts(gpu, &poses, rays, casts)?;
    let ms = |time: Duration| time.as_secs_f64() * 1e3;
    let copies_cast = f64::from(copies);
    Ok(ThroughputRow {
        sweeps_per_cast: copies,
        timed_casts: casts.timed,
        gpu_median_ms: ms(median(&gpu_times)),
        gpu_p90_ms: ms(p90(&gpu_times)),
        wall_median_ms: ms(median(&wall_times)),
        wall_p90_ms: ms(p90(&wall_times)),
        sweeps_per_second_gpu: copies_cast / median(&gpu_times).as_secs_f64(),
        sweeps_per_second_wall: copies_cast * f64::from(casts.timed) / wall_total.as_secs_f64(),
        same_as_alone: sweeps_cast.iter().all(|sweep| sweep == alone),
    })
}

/// The map of `MAP_SWEEPS` placed by their poses, prepped with the defaults.
fn prepped_map(data: &Path, poses: &SweepPoses) -> Result<PatchSet, BenchError> {
    let paths = MAP_SWEEPS
        .iter()
        .map(|name| data_file(data, &Path::new(SEQUENCE).join(name)))
        .collect::<Result<Vec<_>, _>>()?;
    let names: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    let placed = poses.for_sweeps(&names, &data.join(SEQUENCE).join(POSES))?;
    let clouds = paths
        .iter()
        .map(|path| pointray_io::formats::read_point_cloud(path))
        .collect::<Result<Vec<_>, _>>()?;
    let cloud = pointray_io::sweep_map(clouds, &placed, &names)?;
    let (patches, _) = pointray_surface::prep(&cloud, &PrepSettings::default(), &NoProgress)
        .map_err(|source| BenchError::Prep { case: CASE.to_owned(), source })?;
    Ok(patches)
}

type Timings = (Vec<Duration>, Vec<Duration>, Duration, Vec<Vec<Option<f64>>>);

/// The GPU and wall time of each timed re-simulation from `poses`, the wall time of them
/// all, and the last one's sweeps.
fn timed_casts(
    gpu: &GpuMapCaster,
    poses: &[DAffine3],
    rays: &SweepRays,
    sweeps: FrameCounts,
) -> Result<Timings, BenchError> {
    let cast =
        |caster: &dyn MapCaster| resimulate_from(caster, poses, rays, MAX_RANGE_M).map_err(lidar_error);
    let mut ranges = Vec::new();
    for _ in 0..sweeps.warmup {
        ranges = cast(gpu)?;
    }
    let (mut gpu_times, mut wall_times) = (Vec::new(), Vec::new());
    let started = Instant::now();
    for _ in 0..sweeps.timed {
        let sweep_started = Instant::now();
        ranges = cast(gpu)?;
        wall_times.push(sweep_started.elapsed());
        gpu_times.push(gpu.last_timing().and_then(|timing| timing.gpu).unwrap_or_default());
    }
    Ok((gpu_times, wall_times, started.elapsed(), ranges))
}

fn backend_error(source: pointray_render::BackendError) -> BenchError {
    BenchError::Backend { case: CASE.to_owned(), source }
}

fn lidar_error(source: pointray_lidar::LidarError) -> BenchError {
    BenchError::Lidar { case: CASE.to_owned(), source: Box::new(source) }
}

/// The report as a markdown table.
pub fn resim_markdown(report: &ResimReport) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "# Re-simulation throughput\n\ndevice: {}\n", report.device);
    let _ = writeln!(
        text,
        "map: {} ({} patches, prep {:.2} s, upload {:.2} s); cast: {} ({} rays)\n",
        report.map_sweeps.join(" + "),
        report.map_patches,
        report.prep_seconds,
        report.upload_seconds,
        report.cast_sweep,
        report.rays
    );
    let _ = writeln!(
        text,
        "| sweeps a cast | casts | GPU median ms | GPU p90 ms | wall median ms | wall p90 ms | sweeps/s (GPU) | sweeps/s (wall) | same as alone |\n|---|---|---|---|---|---|---|---|---|"
    );
    for row in &report.throughput {
        let _ = writeln!(
            text,
            "| {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.0} | {:.0} | {} |",
            row.sweeps_per_cast,
            row.timed_casts,
            row.gpu_median_ms,
            row.gpu_p90_ms,
            row.wall_median_ms,
            row.wall_p90_ms,
            row.sweeps_per_second_gpu,
            row.sweeps_per_second_wall,
            row.same_as_alone
        );
    }
    let _ = writeln!(text, "\nthe CPU caster, one sweep: {:.1} ms\n", report.cpu_sweep_ms);
    let (cpu, real) = (&report.against_cpu, &report.against_real);
    let _ = writeln!(
        text,
        "against the CPU caster: {:.3}% of rays agree (hit or miss differs on {}, range beyond {} m on {}, largest difference {:.4} m)",
        100.0 * cpu.agreeing_fraction,
        cpu.hit_or_miss_differs,
        cpu.tolerance,
        cpu.range_differs,
        cpu.largest_range_difference
    );
    let _ = writeln!(
        text,
        "against the real sweep: {:.2}% agree, Chamfer {}",
        100.0 * real.agreeing_fraction,
        real.chamfer.map_or("-".to_owned(), |c| format!("{c:.3} m"))
    );
    text
}
