//! `pointray prep`: a points file to a patch store (METHOD.md §2).

use std::path::PathBuf;

use clap::Args;
use pointray_surface::prep_owned;

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
    let (patches, report) =
        prep_owned(cloud, &settings, &bar).map_err(|e| anyhow::anyhow!("{}: {e}", args.points.display()))?;
    pointray_surface::patch_store::write(&args.output, &patches)?;
    println!("{report}");
    println!("wrote {} patches to {} (offset stored in its header)", patches.len(), args.output.display());
    Ok(())
}
