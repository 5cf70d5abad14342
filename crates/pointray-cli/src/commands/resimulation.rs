//! `pointray scan MAP.patches --rays-from SWEEP --pose …`: a real sweep's rays cast from a pose
//! into a prepped map, written as a sweep in the real one's layout and scored against it.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

use clap::Args;
use glam::DAffine3;
use pointray_io::{MemoryBudget, SweepPoses};
use pointray_lidar::{RangeAgreement, SweepRays, resimulate};
use pointray_render::{BackendChoice, DeviceSelector};

use crate::backend::{backend_choice, open_backend};

/// The map's ranges reach this far by default (metres): past the farthest return of the
/// automotive sensors that sweeps come from.
const DEFAULT_MAX_RANGE: f64 = 200.0;

#[derive(Args, Debug)]
pub struct ResimulationArgs {
    /// Cast the rays of this real sweep (a KITTI-layout .bin) into the map given as the scene
    /// (a patch store from `prep`), from `--pose` or `--poses`, instead of a preset's.
    #[arg(long, value_name = "SWEEP")]
    pub rays_from: Option<PathBuf>,
    /// The sensor's pose in the map's coordinates: 12 numbers (a KITTI 3x4 row-major line) or
    /// 16 (4x4), separated by spaces or commas.
    #[arg(long, requires = "rays_from", conflicts_with = "poses", allow_hyphen_values = true)]
    pose: Option<String>,
    /// A poses file (one pose a line); the sweep's pose is the line its file name numbers
    /// (`scan01.bin` takes line 1, from 0), or `--frame`.
    #[arg(long, requires = "rays_from")]
    poses: Option<PathBuf>,
    /// The line of `--poses` to take.
    #[arg(long, requires = "poses")]
    frame: Option<usize>,
    /// Write the comparison with the real sweep as JSON.
    #[arg(long, requires = "rays_from")]
    json: Option<PathBuf>,
    /// Where `--rays-from`'s rays are cast: `auto` (the default) takes a hardware ray-tracing
    /// GPU if there is one, otherwise the CPU backend.
    #[arg(long, value_parser = backend_choice(), requires = "rays_from")]
    backend: Option<BackendChoice>,
    /// Vulkan device: `auto` (the default), an index from `pointray devices`, or part of its
    /// name.
    #[arg(long, requires = "rays_from")]
    device: Option<DeviceSelector>,
    /// GPU memory the map may take, building included, e.g. `40G` (default: the device's).
    #[arg(long = "gpu-memory", value_name = "SIZE", value_parser = MemoryBudget::from_str, requires = "rays_from")]
    gpu_memory: Option<MemoryBudget>,
}

/// Re-simulates the sweep `rays_from` in `map` and writes it to `output`.
pub fn run(
    resimulation: &ResimulationArgs,
    sweep: &Path,
    map: &Path,
    output: &Path,
    max_range: Option<f64>,
) -> anyhow::Result<()> {
    let outputs: Vec<PathBuf> =
        std::iter::once(output.to_path_buf()).chain(resimulation.json.clone()).collect();
    let inputs: Vec<PathBuf> =
        [sweep, map].into_iter().map(Path::to_path_buf).chain(resimulation.poses.clone()).collect();
    pointray_io::ensure_outputs_spare_inputs(&inputs, &outputs)?;
    anyhow::ensure!(
        output.extension().is_some_and(|extension| extension.eq_ignore_ascii_case("bin")),
        "{}: a re-simulated sweep is written in the real sweep's layout (KITTI .bin); name the output *.bin",
        output.display()
    );
    let pose = pose_of(resimulation, sweep)?;
    let real = pointray_io::formats::read_point_cloud(sweep)?;
    let rays = SweepRays::of_sweep(&real);
    let patches = pointray_patches::patch_store::read(map)?;
    let device = resimulation.device.clone().unwrap_or(DeviceSelector::Auto);
    let backend = open_backend(resimulation.backend.unwrap_or_default(), &device, resimulation.gpu_memory)?;
    println!("backend: {}", backend.describe());
    let caster = backend.map_caster(Arc::new(patches))?;
    let started = Instant::now();
    let ranges = resimulate(caster.as_ref(), &pose, &rays, max_range.unwrap_or(DEFAULT_MAX_RANGE))?;
    let seconds = started.elapsed().as_secs_f64();
    write_sweep(output, &rays, &ranges)?;
    let agreement = RangeAgreement::of(&rays, &ranges);
    println!("{}", summary(&agreement, seconds));
    if let Some(json) = &resimulation.json {
        pointray_io::write_atomically(json, |writer| {
            serde_json::to_writer_pretty(&mut *writer, &agreement)?;
            writeln!(writer)
        })?;
    }
    Ok(())
}

/// The pose the sweep is cast from.
fn pose_of(resimulation: &ResimulationArgs, sweep: &Path) -> anyhow::Result<DAffine3> {
    if let Some(pose) = &resimulation.pose {
        let parsed = SweepPoses::parse(pose).map_err(|problem| anyhow::anyhow!("--pose: {problem}"))?;
        anyhow::ensure!(parsed.poses.len() == 1, "--pose takes one pose, not {}", parsed.poses.len());
        return Ok(parsed.poses[0]);
    }
    let Some(path) = &resimulation.poses else { anyhow::bail!("--rays-from needs --pose or --poses") };
    let poses = SweepPoses::read(path)?;
    if let Some(frame) = resimulation.frame {
        return poses.poses.get(frame).copied().ok_or_else(|| {
            anyhow::anyhow!(
                "{}: holds {} poses; --frame {frame} is past them",
                path.display(),
                poses.poses.len()
            )
        });
    }
    Ok(poses.for_sweeps(&[sweep], path)?[0])
}

/// The re-simulated returns in the sensor's frame, as KITTI writes them (x, y, z, intensity);
/// rays that met nothing give no return.
fn write_sweep(output: &Path, rays: &SweepRays, ranges: &[Option<f64>]) -> anyhow::Result<()> {
    pointray_io::write_atomically(output, |writer| {
        for (i, range) in ranges.iter().enumerate() {
            let Some(range) = range else { continue };
            let point = rays.point(i, *range);
            for value in [point.x as f32, point.y as f32, point.z as f32, 0.0] {
                writer.write_all(&value.to_le_bytes())?;
            }
        }
        Ok(())
    })?;
    Ok(())
}

fn summary(agreement: &RangeAgreement, seconds: f64) -> String {
    let metres = |value: Option<f64>| value.map_or("-".to_owned(), |v| format!("{v:.3} m"));
    format!(
        "re-simulated {} rays in {seconds:.2} s: {:.2} % agree within max({} m, {} x range), median range error {}, \
         Chamfer {} (re-simulated to real {}, real to re-simulated {}), {} floaters, {} beyond, {} misses",
        agreement.rays,
        agreement.agreeing_fraction * 100.0,
        pointray_lidar::range_agreement::ABSOLUTE_TOLERANCE,
        pointray_lidar::range_agreement::RANGE_TOLERANCE,
        metres(agreement.median_abs_range_error),
        metres(agreement.chamfer),
        metres(agreement.chamfer_simulated_to_real),
        metres(agreement.chamfer_real_to_simulated),
        agreement.floaters,
        agreement.beyond,
        agreement.misses
    )
}
