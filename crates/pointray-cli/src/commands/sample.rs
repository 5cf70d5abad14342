//! `pointray sample`: area-weighted points on a triangle mesh (the benchmark stand-ins).

use std::path::PathBuf;

use clap::Args;
use pointray_io::MemoryBudget;

/// Sample points uniformly (by area) on a triangle mesh's surface.
#[derive(Args)]
pub struct SampleArgs {
    /// The triangle mesh (PLY or OBJ).
    mesh: PathBuf,
    /// The points file to write (binary PLY).
    #[arg(short, long)]
    output: PathBuf,
    /// How many points.
    #[arg(long)]
    count: u64,
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
}

impl SampleArgs {
    /// The part to write, (I, N); the whole sample is part 0 of 1.
    fn part(&self) -> anyhow::Result<(usize, usize)> {
        let (tile, of) = (self.tile.unwrap_or(0), self.of.unwrap_or(1));
        anyhow::ensure!(tile < of, "--tile {tile} is not one of --of {of} parts (0 to {})", of - 1);
        anyhow::ensure!(
            u64::from(of) <= self.count,
            "--of {of} parts of --count {} leaves parts empty",
            self.count
        );
        Ok((tile as usize, of as usize))
    }

    /// How many points the part holds: its share of `--count`.
    fn part_count(&self, (index, parts): (usize, usize)) -> u64 {
        let share = |part: usize| (u128::from(self.count) * part as u128 / parts as u128) as u64;
        share(index + 1) - share(index)
    }
}

pub fn run(args: SampleArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.count > 0, "--count must be at least 1");
    // Another extension would name PLY bytes as a format they are not.
    anyhow::ensure!(
        args.output.extension().is_some_and(|extension| extension.eq_ignore_ascii_case("ply")),
        "{}: sample writes binary PLY; name the output *.ply",
        args.output.display()
    );
    pointray_io::ensure_outputs_spare_inputs(
        std::slice::from_ref(&args.mesh),
        std::slice::from_ref(&args.output),
    )?;
    let part = args.part()?;
    let bytes_each = pointray_surface::sampling::bytes_per_sample(args.blue_noise);
    MemoryBudget::of_this_machine()
        .check(args.part_count(part), bytes_each, "points")
        .map_err(|shortfall| anyhow::anyhow!("--count {}: {shortfall}", args.count))?;
    let mesh = pointray_io::formats::read_triangle_mesh(&args.mesh)?;
    anyhow::ensure!(
        !mesh.triangles.is_empty(),
        "{}: the mesh has no triangles to sample",
        args.mesh.display()
    );
    let cloud = if args.blue_noise {
        pointray_surface::sample_mesh(&mesh, args.count as usize, args.seed, true)
    } else {
        pointray_surface::sample_mesh_part(&mesh, args.count as usize, args.seed, part)
    };
    anyhow::ensure!(
        !cloud.is_empty(),
        "{}: the mesh has no area to sample (every triangle is degenerate or names missing vertices)",
        args.mesh.display()
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
