//! `pointray sample`: area-weighted points on a triangle mesh (the benchmark stand-ins), whole
//! or in parts that separate jobs write, and the join of such parts.

use std::path::{Path, PathBuf};

use clap::Args;
use pointray_io::MemoryBudget;

use crate::sample_parts::join_parts;

/// Sample points uniformly (by area) on a triangle mesh's surface.
#[derive(Args)]
pub struct SampleArgs {
    /// The triangle mesh (PLY or OBJ).
    #[arg(required_unless_present = "join")]
    mesh: Option<PathBuf>,
    /// The points file to write (binary PLY).
    #[arg(short, long)]
    output: PathBuf,
    /// How many points.
    #[arg(long, required_unless_present = "join")]
    count: Option<u64>,
    /// The same seed always gives the same points.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Spread the points evenly (Poisson-disk elimination), as real scans are.
    #[arg(long)]
    blue_noise: bool,
    /// Write only part I of the `--of` N (0 to N-1): the points the whole sample holds at
    /// that place, so that N jobs' parts, in order, are the whole sample.
    #[arg(long, value_name = "I", requires = "of", conflicts_with = "blue_noise")]
    tile: Option<u32>,
    /// The number of parts the sample is cut into, with `--tile`.
    #[arg(long, value_name = "N", requires = "tile", value_parser = clap::value_parser!(u32).range(1..=65_536))]
    of: Option<u32>,
    /// Join these parts, in the order given, into the one points file `--output`.
    #[arg(long, value_name = "PARTS", num_args = 1.., conflicts_with_all = ["mesh", "count", "tile", "blue_noise"])]
    join: Vec<PathBuf>,
}

/// The part to write, (I, N), of `count` points; the whole sample is part 0 of 1.
fn part_of(args: &SampleArgs, count: u64) -> anyhow::Result<(usize, usize)> {
    let (tile, of) = (args.tile.unwrap_or(0), args.of.unwrap_or(1));
    anyhow::ensure!(tile < of, "--tile {tile} is not one of --of {of} parts (0 to {})", of - 1);
    anyhow::ensure!(u64::from(of) <= count, "--of {of} parts of --count {count} leaves parts empty");
    Ok((tile as usize, of as usize))
}

/// How many points part (I, N) of `count` holds.
fn part_count(count: u64, (index, parts): (usize, usize)) -> u64 {
    let share = |part: usize| (u128::from(count) * part as u128 / parts as u128) as u64;
    share(index + 1) - share(index)
}

pub fn run(args: SampleArgs) -> anyhow::Result<()> {
    // Another extension would name PLY bytes as a format they are not.
    anyhow::ensure!(
        args.output.extension().is_some_and(|extension| extension.eq_ignore_ascii_case("ply")),
        "{}: sample writes binary PLY; name the output *.ply",
        args.output.display()
    );
    match (&args.mesh, args.count) {
        (Some(mesh), Some(count)) => sample(&args, mesh, count),
        _ => join(&args.join, &args.output),
    }
}

fn sample(args: &SampleArgs, mesh_path: &Path, count: u64) -> anyhow::Result<()> {
    anyhow::ensure!(count > 0, "--count must be at least 1");
    pointray_io::ensure_outputs_spare_inputs(&[mesh_path.to_path_buf()], std::slice::from_ref(&args.output))?;
    let part = part_of(args, count)?;
    let bytes_each = pointray_surface::sampling::bytes_per_sample(args.blue_noise);
    MemoryBudget::of_this_machine()
        .check(part_count(count, part), bytes_each, "points")
        .map_err(|shortfall| anyhow::anyhow!("--count {count}: {shortfall}"))?;
    let mesh = pointray_io::formats::read_triangle_mesh(mesh_path)?;
    anyhow::ensure!(
        !mesh.triangles.is_empty(),
        "{}: the mesh has no triangles to sample",
        mesh_path.display()
    );
    let cloud = if args.blue_noise {
        pointray_surface::sample_mesh(&mesh, count as usize, args.seed, true)
    } else {
        pointray_surface::sample_mesh_part(&mesh, count as usize, args.seed, part)
    };
    anyhow::ensure!(
        !cloud.is_empty(),
        "{}: the mesh has no area to sample (every triangle is degenerate or names missing vertices)",
        mesh_path.display()
    );
    pointray_io::formats::ply::write_point_cloud(&args.output, &cloud)?;
    match (args.tile, args.of) {
        (Some(tile), Some(of)) => {
            println!("wrote part {tile} of {of} ({} points) to {}", cloud.len(), args.output.display())
        }
        _ => println!("wrote {} points to {}", cloud.len(), args.output.display()),
    }
    Ok(())
}

fn join(parts: &[PathBuf], output: &Path) -> anyhow::Result<()> {
    pointray_io::ensure_outputs_spare_inputs(parts, &[output.to_path_buf()])?;
    let points = join_parts(parts, output)?;
    println!("joined {} parts, {points} points, into {}", parts.len(), output.display());
    Ok(())
}
