//! `pointray prep`: a points file to a patch store (METHOD.md §2).

use std::path::PathBuf;

use clap::Args;
use pointray_surface::tiled_prep::prep_tiled;
use pointray_surface::{PrepError, prep_owned};

use crate::columns_arg::ColumnsArg;
use crate::prep_settings_args::PrepSettingsArgs;
use crate::progress::PrepBar;

/// Fit an MLS quadratic patch to every point and write the patch store.
#[derive(Args)]
pub struct PrepArgs {
    /// The points file (PLY, LAS/LAZ, PCD, E57, XYZ/CSV, KITTI .bin).
    points: PathBuf,
    /// The patch store to write.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    settings: PrepSettingsArgs,
    /// Prep in this many tiles, one after another, each with a halo of its neighbours'
    /// points: the same patches where they depend only on their neighbourhoods, in the
    /// memory of the cloud and one tile (normals oriented over the neighbour graph are
    /// settled per tile; orient toward `--sensor` for identical ones).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=65_536))]
    tiles: Option<u32>,
    #[command(flatten)]
    columns: ColumnsArg,
}

pub fn run(args: PrepArgs) -> anyhow::Result<()> {
    pointray_io::ensure_outputs_spare_inputs(
        std::slice::from_ref(&args.points),
        std::slice::from_ref(&args.output),
    )?;
    let settings = args.settings.settings()?;
    let cloud = args.columns.read_point_cloud(&args.points)?;
    let bar = PrepBar::default();
    let in_file = |e: PrepError| anyhow::anyhow!("{}: {e}", args.points.display());
    let patches = match args.tiles {
        Some(tiles) => {
            let patches = prep_tiled(&cloud, &settings, tiles as usize, &bar).map_err(in_file)?;
            println!("prepped {} points in {tiles} tiles into {} patches", cloud.len(), patches.len());
            patches
        }
        None => {
            let (patches, report) = prep_owned(cloud, &settings, &bar).map_err(in_file)?;
            println!("{report}");
            patches
        }
    };
    pointray_surface::patch_store::write(&args.output, &patches)?;
    println!("wrote {} patches to {} (offset stored in its header)", patches.len(), args.output.display());
    Ok(())
}
