//! `pointray prep`: a points file to a patch store (METHOD.md §2), in memory when the cloud
//! fits the budget, else tile by tile from a cloud read in chunks; or one tile of a cut as a
//! separate job, and the merge of such tiles.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use pointray_io::{MemoryBudget, PointStream, SweepPoses};
use pointray_patches::PrepSettings;
use pointray_surface::peak_memory::peak_rss;
use pointray_surface::prep_memory::{PrepRoute, prep_route};
use pointray_surface::tiles::kept_sort::{is_kept_sort, keep_sort};
use pointray_surface::tiles::merge::{MergeSummary, MergedTiles, merge_tile_files};
use pointray_surface::tiles::streamed_prep::{prep_kept_streamed, prep_streamed, prep_tile_job};
use pointray_surface::tiles::streamed_tiles::TileCount;
use pointray_surface::{PrepError, prep_owned};

use crate::columns_arg::ColumnsArg;
use crate::prep_settings_args::PrepSettingsArgs;
use crate::progress::PrepBar;
use std::str::FromStr;

/// Fit an MLS quadratic patch to every point and write the patch store.
#[derive(Args)]
pub struct PrepArgs {
    /// The points file (PLY, LAS/LAZ, PCD, E57, XYZ/CSV, KITTI .bin), or several sweeps with
    /// `--poses`, merged into one map.
    #[arg(required_unless_present = "merge")]
    points: Vec<PathBuf>,
    /// The sweeps' sensor poses in the map: one pose a line (KITTI's 3x4 row-major, or 4x4),
    /// one per sweep in order, or else the line each sweep's file name numbers.
    #[arg(long, conflicts_with_all = ["tiles", "tile", "merge"])]
    poses: Option<PathBuf>,
    /// The patch store to write (with `--tile`, the tile file).
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    settings: PrepSettingsArgs,
    /// Prep in at least this many tiles, one after another, each with a halo of its
    /// neighbours' points: the same patches where they depend only on their neighbourhoods
    /// (normals oriented over the neighbour graph are settled per tile; orient toward
    /// `--sensor` for identical ones). A cloud over the memory budget is tiled anyway.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65_536), conflicts_with_all = ["tile", "merge"])]
    tiles: Option<u32>,
    /// Prep only tile I of the `--of` N (0 to N-1) and write it alone, for `--merge`.
    #[arg(long, value_name = "I", requires = "of", conflicts_with = "merge")]
    tile: Option<u32>,
    /// The number of tiles the cloud is cut into, with `--tile`.
    #[arg(long, value_name = "N", requires = "tile", value_parser = clap::value_parser!(u32).range(1..=65_536))]
    of: Option<u32>,
    /// Sort the cloud along its curve once and keep the sort in the new folder `--output`:
    /// tile jobs given that folder as their points (`--tile I --of N`) then read only their
    /// tiles, where each would otherwise read and sort the whole cloud; prep given the folder
    /// alone preps every tile, as `--tiles` does, without sorting again.
    #[arg(long, conflicts_with_all = ["tiles", "tile", "merge", "poses", "scratch"])]
    keep_sort: bool,
    /// Merge these tile files (every tile of one cut) into the store `--output`.
    #[arg(long, value_name = "TILE_FILES", num_args = 1.., conflicts_with = "points")]
    merge: Vec<PathBuf>,
    /// Remove each tile file as soon as its records are in the store, once every tile has been
    /// read and checked: for a disk that cannot hold the tiles and the store at once. A merge
    /// that fails after that leaves the removed tiles to be prepped again.
    #[arg(long, requires = "merge")]
    remove_tiles: bool,
    /// The memory prep may use, e.g. `8G` or `512M` (default: half the machine's RAM).
    #[arg(long, value_parser = MemoryBudget::from_str)]
    memory: Option<MemoryBudget>,
    /// The folder prep in tiles sorts the points in (default: the output's). It holds about
    /// 36 bytes a point, more with attributes: a folder in memory such as /dev/shm where the
    /// output's disk cannot hold them beside the store.
    #[arg(long, value_name = "DIR")]
    scratch: Option<PathBuf>,
    #[command(flatten)]
    columns: ColumnsArg,
}

impl PrepArgs {
    /// The folder the scratch folder is made in.
    fn scratch(&self) -> &Path {
        self.scratch.as_deref().unwrap_or_else(|| pointray_io::folder_of(&self.output))
    }
}

pub fn run(args: PrepArgs) -> anyhow::Result<()> {
    let inputs: Vec<PathBuf> = args.points.iter().chain(&args.merge).chain(&args.poses).cloned().collect();
    pointray_io::ensure_outputs_spare_inputs(&inputs, std::slice::from_ref(&args.output))?;
    let memory = args.memory.unwrap_or_else(MemoryBudget::half_of_this_machine);
    let bar = PrepBar::default();
    if let Some(poses) = &args.poses {
        return prep_sweep_map(&args.points, poses, &args, &bar);
    }
    anyhow::ensure!(args.points.len() <= 1, "several points files are sweeps of one map: give their --poses");
    let Some(points) = args.points.first() else {
        let tiles = if args.remove_tiles { MergedTiles::Removed } else { MergedTiles::Kept };
        let merged = merge_tile_files(&args.merge, &args.output, (memory, tiles), &bar)?;
        report_store(&merged, &args.output);
        return Ok(());
    };
    let settings = args.settings.settings()?;
    if let (Some(tile), Some(of)) = (args.tile, args.of) {
        return run_tile_job(points, &settings, (tile, of), memory, &args, &bar);
    }
    if args.keep_sort {
        let mut stream = args.columns.open_stream(points, memory)?;
        let sorted = keep_sort(&mut stream, &settings, memory, &args.output, &bar)?;
        println!("sorted {sorted} points into {} for tile jobs", args.output.display());
        return Ok(());
    }
    let started = Instant::now();
    let count = TileCount::AtLeast(args.tiles.unwrap_or(1) as usize);
    let merged = if is_kept_sort(points) {
        prep_kept_streamed(points, &settings, (count, memory), &args.output, &bar)?
    } else {
        let mut stream = args.columns.open_stream(points, memory)?;
        let route = prep_route(stream.len(), &settings, stream.attribute_bytes_per_point(), memory);
        if args.tiles.is_none() && route == PrepRoute::InMemory {
            return prep_in_memory(stream, started, &args, &settings, &bar);
        }
        let places = (args.output.as_path(), args.scratch());
        prep_streamed(&mut stream, &settings, (count, memory), places, &bar)?
    };
    // The process's own high-water mark, which tests and job scripts read back.
    let peak =
        peak_rss().map_or_else(String::new, |bytes| format!(" (peak resident memory {} KiB)", bytes >> 10));
    let (points, tiles, budget) = (merged.input_points, merged.tiles, memory.bytes >> 20);
    println!("prepped {points} points in {tiles} tiles within {budget} MiB{peak}");
    for (stage, elapsed) in bar.stage_times() {
        println!("  {:<22} {:>8.3} s", stage.name(), elapsed.as_secs_f64());
    }
    report_store(&merged, &args.output);
    Ok(())
}

/// Preps tile `tile` of `of` of the cloud `points`, or of the sort kept in that folder.
fn run_tile_job(
    points: &Path,
    settings: &PrepSettings,
    (tile, of): (u32, u32),
    memory: MemoryBudget,
    args: &PrepArgs,
    bar: &PrepBar,
) -> anyhow::Result<()> {
    let cut = (tile as usize, of as usize);
    let places = (args.output.as_path(), args.scratch());
    let owned = prep_tile_job(points, args.columns.columns(), settings, cut, memory, places, bar)?;
    println!("wrote tile {tile} of {of} ({owned} points of its own) to {}", args.output.display());
    Ok(())
}

/// Preps the cloud of `stream`, opened at `started`, in memory: a file the stream read whole
/// is not read again (which would also repeat its warnings).
fn prep_in_memory(
    stream: PointStream,
    started: Instant,
    args: &PrepArgs,
    settings: &PrepSettings,
    bar: &PrepBar,
) -> anyhow::Result<()> {
    let points = stream.path().to_path_buf();
    let cloud = match stream.into_whole_cloud() {
        Some(cloud) => cloud,
        None => args.columns.read_point_cloud(&points)?,
    };
    // Reading and writing sit outside prep's stages, and at a billion points take as long.
    println!("read {} points in {:.3} s", cloud.len(), started.elapsed().as_secs_f64());
    prep_and_write(cloud, &points.display().to_string(), args, settings, bar)
}

/// Several sweeps placed by their poses and prepped as one map: each sweep is a station of
/// the scan's structure, so its patches follow its own lines.
fn prep_sweep_map(sweeps: &[PathBuf], poses: &Path, args: &PrepArgs, bar: &PrepBar) -> anyhow::Result<()> {
    let started = Instant::now();
    let placed = SweepPoses::read(poses)?.for_sweeps(sweeps, poses)?;
    let clouds =
        sweeps.iter().map(|sweep| args.columns.read_point_cloud(sweep)).collect::<Result<Vec<_>, _>>()?;
    let names: Vec<&Path> = sweeps.iter().map(PathBuf::as_path).collect();
    let map = pointray_io::sweep_map(clouds, &placed, &names)?;
    println!(
        "read {} sweeps, {} points, in {:.3} s",
        sweeps.len(),
        map.len(),
        started.elapsed().as_secs_f64()
    );
    let settings = args.settings.settings()?;
    prep_and_write(map, &format!("the map of {}", poses.display()), args, &settings, bar)
}

/// Preps `cloud` (named `source` in errors) in memory and writes the store.
fn prep_and_write(
    cloud: pointray_io::PointCloud,
    source: &str,
    args: &PrepArgs,
    settings: &PrepSettings,
    bar: &PrepBar,
) -> anyhow::Result<()> {
    let in_file = |e: PrepError| anyhow::anyhow!("{source}: {e}");
    let (patches, report) = prep_owned(cloud, settings, bar).map_err(in_file)?;
    println!("{report}");
    let started = Instant::now();
    pointray_patches::patch_store::write_with_scan(&args.output, &patches, &report.scan_structure())?;
    println!(
        "wrote {} patches to {} (offset stored in its header) in {:.3} s",
        patches.len(),
        args.output.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn report_store(merged: &MergeSummary, output: &Path) {
    println!(
        "wrote {} patches of {} tiles to {} (offset stored in its header)",
        merged.patches,
        merged.tiles,
        output.display()
    );
}
