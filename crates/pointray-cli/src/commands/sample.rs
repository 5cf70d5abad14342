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
    let bytes_each = pointray_surface::sampling::bytes_per_sample(args.blue_noise);
    MemoryBudget::of_this_machine()
        .check(args.count, bytes_each, "points")
        .map_err(|shortfall| anyhow::anyhow!("--count {}: {shortfall}", args.count))?;
    let mesh = pointray_io::formats::read_triangle_mesh(&args.mesh)?;
    anyhow::ensure!(
        !mesh.triangles.is_empty(),
        "{}: the mesh has no triangles to sample",
        args.mesh.display()
    );
    let cloud = pointray_surface::sample_mesh(&mesh, args.count as usize, args.seed, args.blue_noise);
    anyhow::ensure!(
        !cloud.is_empty(),
        "{}: the mesh has no area to sample (every triangle is degenerate or names missing vertices)",
        args.mesh.display()
    );
    pointray_io::formats::ply::write_point_cloud(&args.output, &cloud)?;
    println!("wrote {} points to {}", cloud.len(), args.output.display());
    Ok(())
}
