//! `pointray scan`: a simulated LiDAR scan of the procedural street or of a scene file.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::{ArgGroup, Args};
use glam::DVec3;
use indicatif::{ProgressBar, ProgressStyle};
use pointray_io::MemoryBudget;
use pointray_lidar::{LidarScene, Scan, ScanProgress, Sensor, SensorPose, SensorPreset, Surface, UpAxis};

use super::resimulation::{self, ResimulationArgs};
use crate::point_arg::parse_point;

/// Scans past this many rays show a progress bar.
const RAYS_FOR_BAR: u64 = 1_000_000;

/// Cast a virtual LiDAR's rays into the street or a scene's meshes and write the returns
/// (position, intensity, ring, azimuth, time, ASPRS class, sensor origin) as binary PLY.
#[derive(Args)]
#[command(group(ArgGroup::new("world").required(true).args(["scene", "street"])))]
pub struct ScanArgs {
    /// A scene file to scan (Y up, as all scene files are); objects are classified by name.
    scene: Option<PathBuf>,
    /// Scan the built-in street (Z up) instead, with the bunny and horse on its road when the
    /// data folder ($POINTRAY_DATA, else the checkout's data/) has them.
    #[arg(long)]
    street: bool,
    /// hdl64, hdl32, vlp16, os128 (spinning, at 10 Hz) or terrestrial (a tripod scanner).
    #[arg(long, required_unless_present = "rays_from", conflicts_with = "rays_from")]
    sensor: Option<SensorPreset>,
    /// The sensor's position, x,y,z. On the street it defaults to the middle of the road at
    /// the sensor's mount height; a scene file needs one.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true, conflicts_with = "stations")]
    position: Option<DVec3>,
    /// Several stations merged into one cloud, each point keeping its own: x,y,z;x,y,z;…
    #[arg(long, value_parser = parse_point, value_delimiter = ';', allow_hyphen_values = true)]
    stations: Vec<DVec3>,
    /// The sensor's heading in degrees, counterclockwise seen from above from +X.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    yaw: f64,
    /// Sigma of the Gaussian range noise (default: the sensor's, 2–3 cm, 2 mm terrestrial).
    #[arg(long, allow_negative_numbers = true)]
    noise: Option<f64>,
    /// Probability that a return is lost (default 0).
    #[arg(long, allow_negative_numbers = true)]
    dropout: Option<f64>,
    /// Returns nearer than this are discarded (default: the sensor's).
    #[arg(long, allow_negative_numbers = true)]
    min_range: Option<f64>,
    /// Surfaces beyond this give no return (default: the sensor's).
    #[arg(long, allow_negative_numbers = true)]
    max_range: Option<f64>,
    /// Degrees between columns (default: the sensor's); a terrestrial scanner spaces its rows
    /// the same.
    #[arg(long, allow_negative_numbers = true)]
    azimuth_step: Option<f64>,
    /// The same seed always gives the same noise and dropouts.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// The points file to write (binary PLY).
    #[arg(short, long)]
    output: PathBuf,
    /// Also write the street as a mesh (PLY), the ground truth for `pointray fidelity`.
    #[arg(long)]
    mesh_out: Option<PathBuf>,
    #[command(flatten)]
    resimulation: ResimulationArgs,
}

pub fn run(args: ScanArgs) -> anyhow::Result<()> {
    if let Some(sweep) = &args.resimulation.rays_from {
        let Some(map) = &args.scene else {
            anyhow::bail!("--rays-from casts into a prepped map: give its patch store")
        };
        return resimulation::run(&args.resimulation, sweep, map, &args.output, args.max_range);
    }
    anyhow::ensure!(
        args.mesh_out.is_none() || args.street,
        "--mesh-out writes the built-in street's mesh, so it needs --street (a scene file's meshes are already files)"
    );
    let Some(preset) = args.sensor else {
        anyhow::bail!("give --sensor, or --rays-from to cast a real sweep's rays")
    };
    let sensor = configured_sensor(&args, preset);
    sensor.validate()?;
    let world = World::open(&args)?;
    check_outputs(&args, &world.inputs)?;
    let stations = stations(&args, &sensor, world.scene.up())?;
    price_rays(
        sensor.rays_per_sweep().saturating_mul(stations.len() as u64),
        MemoryBudget::of_this_machine(),
    )?;
    let started = Instant::now();
    let bar = ScanBar::for_scan(&sensor, stations.len());
    let scanned = pointray_lidar::scan(&world.scene, &sensor, &stations, args.seed, &bar)?;
    bar.finish();
    let elapsed = started.elapsed();
    anyhow::ensure!(
        !scanned.returns.is_empty(),
        "no returns: nothing lies within {}–{} m of the sensor (check --position and the ranges)",
        sensor.min_range,
        sensor.max_range
    );
    println!("{}", summary(&scanned, &sensor, stations.len(), &world.description, elapsed));
    write_outputs(&args, &world, &scanned, &sensor, stations.len())
}

/// Refuses a scan whose returns would not fit in `budget`: each ray may return, and the
/// returns are held twice while the columns' are gathered into one list (measured: about 120
/// bytes a ray).
fn price_rays(rays: u64, budget: MemoryBudget) -> anyhow::Result<()> {
    let bytes_each = 2 * std::mem::size_of::<pointray_lidar::Return>() as u64;
    budget.check(rays, bytes_each, "rays").map_err(|shortfall| anyhow::anyhow!("the scan's {shortfall}"))
}

/// The points file, and the street's mesh when asked for.
fn write_outputs(
    args: &ScanArgs,
    world: &World,
    scanned: &Scan,
    sensor: &Sensor,
    stations: usize,
) -> anyhow::Result<()> {
    let up = world.scene.up().name();
    let comments = [
        format!("pointray scan: {}, {stations} station(s), seed {}", sensor.name, args.seed),
        format!("scene: {}; up axis {up}", world.description),
    ];
    pointray_lidar::ply_output::write_returns(&args.output, &scanned.returns, &comments)?;
    println!("wrote {} (up axis {up})", args.output.display());
    if let (Some(mesh_out), Some(surfaces)) = (&args.mesh_out, &world.street) {
        let mesh = pointray_lidar::merged_mesh(surfaces);
        pointray_io::formats::ply::write_triangle_mesh(mesh_out, &mesh)?;
        println!("wrote the street's mesh ({} triangles) to {}", mesh.triangles.len(), mesh_out.display());
    }
    Ok(())
}

/// The preset with the command line's overrides.
fn configured_sensor(args: &ScanArgs, preset: SensorPreset) -> Sensor {
    let preset = preset.sensor();
    Sensor {
        range_noise: args.noise.unwrap_or(preset.range_noise),
        dropout: args.dropout.unwrap_or(preset.dropout),
        min_range: args.min_range.unwrap_or(preset.min_range),
        max_range: args.max_range.unwrap_or(preset.max_range),
        azimuth_step_deg: args.azimuth_step.unwrap_or(preset.azimuth_step_deg),
        ..preset
    }
}

/// What is scanned.
struct World {
    scene: LidarScene,
    /// The street's surfaces, for `--mesh-out`.
    street: Option<Vec<Surface>>,
    /// The files it was read from, which no output may replace.
    inputs: Vec<PathBuf>,
    /// A few words for the summary and the output's header.
    description: String,
}

impl World {
    fn open(args: &ScanArgs) -> anyhow::Result<Self> {
        if let Some(path) = &args.scene {
            let scene = LidarScene::from_scene_file(path)?;
            return Ok(Self {
                scene,
                street: None,
                inputs: vec![path.clone()],
                description: path.display().to_string(),
            });
        }
        let data = crate::environment::data_dir();
        let surfaces = pointray_lidar::street::street(Some(&data))?;
        let models = pointray_lidar::street::model_files(&data);
        let names: Vec<String> = models
            .iter()
            .filter_map(|path| path.file_stem())
            .map(|stem| stem.to_string_lossy().into_owned())
            .collect();
        let description = if names.is_empty() {
            format!("the street (no scanned models under {})", data.display())
        } else {
            format!("the street with the {}", names.join(" and "))
        };
        let scene = LidarScene::from_surfaces(&surfaces, UpAxis::Z)?;
        Ok(Self { scene, street: Some(surfaces), inputs: models, description })
    }
}

/// No output may replace an input or the other output.
fn check_outputs(args: &ScanArgs, inputs: &[PathBuf]) -> anyhow::Result<()> {
    let outputs: Vec<PathBuf> = std::iter::once(args.output.clone()).chain(args.mesh_out.clone()).collect();
    pointray_io::ensure_outputs_spare_inputs(inputs, &outputs)?;
    // Another extension would name the PLY bytes written as a format they are not.
    anyhow::ensure!(
        args.output.extension().is_some_and(|extension| extension.eq_ignore_ascii_case("ply")),
        "{}: scan writes its returns as PLY; name the output *.ply",
        args.output.display()
    );
    if let Some(mesh_out) = &args.mesh_out {
        anyhow::ensure!(
            !same_path(mesh_out, &args.output),
            "--mesh-out and -o name the same file, {}",
            mesh_out.display()
        );
    }
    Ok(())
}

fn same_path(a: &Path, b: &Path) -> bool {
    a == b || matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// The stations of the command line, or on the street one in the middle of the road.
fn stations(args: &ScanArgs, sensor: &Sensor, up: UpAxis) -> anyhow::Result<Vec<SensorPose>> {
    let at = |position| SensorPose { position, yaw_deg: args.yaw };
    if !args.stations.is_empty() {
        return Ok(args.stations.iter().copied().map(at).collect());
    }
    match (args.position, &args.scene) {
        (Some(position), _) => Ok(vec![at(position)]),
        (None, None) => Ok(vec![at(up.vector() * sensor.mount_height)]),
        (None, Some(scene)) => {
            anyhow::bail!(
                "{}: a scene file has no default sensor position; give --position x,y,z",
                scene.display()
            )
        }
    }
}

fn summary(scanned: &Scan, sensor: &Sensor, stations: usize, description: &str, elapsed: Duration) -> String {
    let stats = &scanned.stats;
    format!(
        "scanned {description} with the {} from {stations} station(s): {} returns of {} rays \
         ({} missed, {} dropped, {} out of range) in {:.2} s",
        sensor.name,
        stats.returns,
        stats.rays,
        stats.misses,
        stats.dropped,
        stats.out_of_range,
        elapsed.as_secs_f64()
    )
}

/// A bar over the scan's columns, for scans long enough to want one.
struct ScanBar(Option<ProgressBar>);

impl ScanBar {
    fn for_scan(sensor: &Sensor, stations: usize) -> Self {
        let rays = sensor.rays_per_sweep().saturating_mul(stations as u64);
        if rays < RAYS_FOR_BAR {
            return Self(None);
        }
        let style = ProgressStyle::with_template("{msg:>20} [{bar:40}] {percent}% {elapsed}")
            .expect("a valid template");
        let columns = u64::from(sensor.columns()) * stations as u64;
        let bar = ProgressBar::new(columns).with_message("scanning").with_style(style);
        bar.enable_steady_tick(Duration::from_millis(200));
        Self(Some(bar))
    }

    fn finish(&self) {
        if let Some(bar) = &self.0 {
            bar.finish_and_clear();
        }
    }
}

impl ScanProgress for ScanBar {
    fn columns_done(&self, count: u64) {
        if let Some(bar) = &self.0 {
            bar.inc(count);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_are_priced_against_the_memory_budget() {
        let budget = MemoryBudget { bytes: 1 << 30 };
        price_rays(4_000_000, budget).expect("4M rays fit in 1 GiB");
        let message = price_rays(57_600_000, budget).unwrap_err().to_string();
        assert!(message.contains("57600000 rays") && message.contains("of memory"), "{message}");
    }
}
