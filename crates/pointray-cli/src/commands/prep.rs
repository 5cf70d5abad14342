//! `pointray prep`: a points file to a patch store (SPEC.md §2).

use std::path::PathBuf;

use clap::Args;
use glam::DVec3;
use pointray_surface::input_validation::validate_options;
use pointray_surface::tiled_prep::prep_tiled;
use pointray_surface::{OutlierFilter, PrepError, PrepOptions, PrepParams, prep_owned};

use crate::boxes_arg::Boxes;
use crate::columns_arg::ColumnsArg;
use crate::progress::PrepBar;
use crate::radius_arg::Radius;
use crate::scan_arg::Scan;

/// Fit an MLS quadratic patch to every point and write the patch store.
#[derive(Args)]
pub struct PrepArgs {
    /// The points file (PLY, LAS/LAZ, PCD, E57, XYZ/CSV, KITTI .bin).
    points: PathBuf,
    /// The patch store to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Neighbours for the support radius and the quadratic fit.
    #[arg(long, default_value_t = 9)]
    k: u32,
    /// Neighbours for the PCA normal.
    #[arg(long, default_value_t = 16)]
    normal_k: u32,
    /// Recompute normals even when the file carries them.
    #[arg(long)]
    recompute_normals: bool,
    /// Orient normals toward this sensor position, `x,y,z` in the file's coordinates.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    sensor: Option<DVec3>,
    /// The box around each patch: the paper's cube of half-size d_i, or a tight box
    /// around the patch over its disk.
    #[arg(long, value_enum, default_value_t = Boxes::Tight)]
    boxes: Boxes,
    /// How far each patch reaches, as a fraction of the paper's support radius d_i (the fit
    /// still uses all k neighbours).
    #[arg(long, default_value_t = PrepParams::default().disk_scale)]
    disk_scale: f32,
    /// Drop statistical outliers first, `K,N`: points whose mean distance to their K
    /// nearest neighbours is more than N standard deviations above the mean (e.g. `8,2`).
    #[arg(long, value_name = "K,N", value_parser = parse_outlier_filter)]
    remove_outliers: Option<OutlierFilter>,
    /// The support radius: by default each disk just covers its point's Voronoi cell (less
    /// false surface and a faster trace than the paper's); `paper` is the farthest of the k
    /// neighbours; `adaptive` grows each disk over the part of its cell that no other disk
    /// covers, held to a band around the neighbourhood's median: fewer holes on scan-line
    /// data, more false surface (bench/FIDELITY.md).
    #[arg(long, value_enum, default_value_t = Radius::Cell)]
    radius: Radius,
    /// LiDAR scans: `auto` shapes elliptical patches along the scan lines (from a ring field,
    /// or beams recovered from elevations) whenever the sensor position is known (the file's,
    /// or `--sensor`); `off` treats every cloud as unstructured points.
    #[arg(long, value_enum, default_value_t = Scan::Auto)]
    scan: Scan,
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
    let params = PrepParams {
        k: args.k,
        normal_k: args.normal_k,
        box_kind: args.boxes.into(),
        disk_scale: args.disk_scale,
        ..PrepParams::default()
    };
    let options = PrepOptions {
        params,
        recompute_normals: args.recompute_normals,
        sensor: args.sensor,
        remove_outliers: args.remove_outliers,
        radius_mode: args.radius.into(),
        scan: args.scan.into(),
    };
    validate_options(&options).map_err(flag_error)?;
    let cloud = args.columns.read_point_cloud(&args.points)?;
    let bar = PrepBar::default();
    let in_file = |e: PrepError| anyhow::anyhow!("{}: {e}", args.points.display());
    let patches = match args.tiles {
        Some(tiles) => {
            let patches = prep_tiled(&cloud, &options, tiles as usize, &bar).map_err(in_file)?;
            println!("prepped {} points in {tiles} tiles into {} patches", cloud.len(), patches.len());
            patches
        }
        None => {
            let (patches, report) = prep_owned(cloud, &options, &bar).map_err(in_file)?;
            println!("{report}");
            patches
        }
    };
    pointray_surface::patch_store::write(&args.output, &patches)?;
    println!("wrote {} patches to {} (offset stored in its header)", patches.len(), args.output.display());
    Ok(())
}

/// A prep setting's error, named by the flag that sets it.
pub fn flag_error(error: PrepError) -> anyhow::Error {
    match error {
        PrepError::InvalidSetting { setting, problem } => {
            let flag = setting.split('.').next().unwrap_or(setting).replace('_', "-");
            anyhow::anyhow!("--{flag}: {problem}")
        }
        other => other.into(),
    }
}

/// Parses `x,y,z`.
pub fn parse_point(text: &str) -> Result<DVec3, String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|part| part.trim().parse::<f64>().map_err(|e| format!("`{part}`: {e}")))
        .collect::<Result<_, _>>()?;
    match values[..] {
        [x, y, z] => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("expected x,y,z, got `{text}`")),
    }
}

/// Parses `K,N` for `--remove-outliers`.
fn parse_outlier_filter(text: &str) -> Result<OutlierFilter, String> {
    let (neighbors, sigmas) = text.split_once(',').ok_or_else(|| format!("expected K,N, got `{text}`"))?;
    let filter = OutlierFilter {
        neighbors: neighbors.trim().parse().map_err(|e| format!("K `{neighbors}`: {e}"))?,
        sigmas: sigmas.trim().parse().map_err(|e| format!("N `{sigmas}`: {e}"))?,
    };
    Ok(filter)
}
