//! `pointray sample`: area-weighted points on a triangle mesh (the benchmark stand-ins).

use std::path::PathBuf;

use clap::Args;

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
    count: usize,
    /// The same seed always gives the same points.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Spread the points evenly (Poisson-disk elimination), as real scans are.
    #[arg(long)]
    blue_noise: bool,
}

pub fn run(args: SampleArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.count > 0, "--count must be at least 1");
    pointray_io::ensure_not_same_file(&args.mesh, &args.output)?;
    let mesh = pointray_io::formats::read_triangle_mesh(&args.mesh)?;
    anyhow::ensure!(
        !mesh.triangles.is_empty(),
        "{}: the mesh has no triangles to sample",
        args.mesh.display()
    );
    let cloud = pointray_surface::sample_mesh(&mesh, args.count, args.seed, args.blue_noise);
    pointray_io::formats::ply::write_point_cloud(&args.output, &cloud)?;
    println!("wrote {} points to {}", cloud.len(), args.output.display());
    Ok(())
}
