//! `pointray consistency`: a scan's patches checked against the sensor's own rays.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::Context;
use clap::Args;
use glam::DVec3;
use pointray_fidelity::{
    ConsistencyOptions, RangeTolerance, ReturnOrigins, sensor_ray_consistency, support_against_beam_spacing,
};

use crate::patch_args::PatchArgs;
use crate::point_arg::parse_finite;

/// Cast each return's ray from its sensor against the points' patches and report the
/// fractions whose first hit agrees with the return, lies well in front of it (floaters) or
/// well behind it or nowhere (holes); with rings, also each patch's support against the beam
/// spacing. Needs no ground truth.
#[derive(Args)]
pub struct ConsistencyArgs {
    /// The scan (any format `prep` reads) with a sensor position or per-point sensor origins.
    points: PathBuf,
    /// Check at most this many returns, drawn at random.
    #[arg(long, default_value_t = ConsistencyOptions::default().rays)]
    rays: usize,
    /// Seeds the draw of returns.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// The tolerance's absolute term, in the file's units (metres for LiDAR).
    #[arg(long, default_value_t = RangeTolerance::default().absolute, allow_hyphen_values = true)]
    abs_tolerance: f64,
    /// The tolerance's term proportional to the range.
    #[arg(long, default_value_t = RangeTolerance::default().range_fraction, allow_hyphen_values = true)]
    range_tolerance: f64,
    /// The tolerance's term in local point spacings (the distance to the 4th nearest return).
    #[arg(long, default_value_t = RangeTolerance::default().spacing_multiple, allow_hyphen_values = true)]
    spacing_tolerance: f64,
    /// The scan's up axis, along which ring elevations are measured.
    #[arg(long, default_value = "0,0,1", value_parser = parse_finite, allow_hyphen_values = true)]
    up: DVec3,
    #[command(flatten)]
    patches: PatchArgs,
    /// Also write the report as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
}

pub fn run(args: ConsistencyArgs) -> anyhow::Result<()> {
    pointray_io::ensure_outputs_spare_inputs(std::slice::from_ref(&args.points), args.json.as_slice())?;
    let options = ConsistencyOptions {
        rays: args.rays,
        seed: args.seed,
        tolerance: RangeTolerance {
            absolute: args.abs_tolerance,
            range_fraction: args.range_tolerance,
            spacing_multiple: args.spacing_tolerance,
        },
        acceptance: args.patches.acceptance(),
        sensor: args.patches.sensor(),
    };
    let context = || format!("checking {} against its sensor's rays", args.points.display());
    options.tolerance.validate().with_context(context)?;
    let prep_settings = args.patches.prep_settings()?;
    let cloud = args.patches.read(&args.points)?;
    // Before the prep, which can take minutes: a scan with no sensor cannot be checked.
    let origins = ReturnOrigins::of_cloud(&cloud, args.patches.sensor()).with_context(context)?;
    let (patches, prep_report) = args.patches.prep(&args.points, &cloud, &prep_settings)?;
    let patches = Arc::new(patches);
    let mut report = sensor_ray_consistency(&cloud, patches.clone(), &options).with_context(context)?;
    if cloud.rings.is_some() {
        let sources = &prep_report.patch_sources;
        let support = support_against_beam_spacing(&cloud, &patches, sources, &origins, args.up.as_vec3())
            .with_context(context)?;
        report.support = Some(support);
    }
    report.points_file = Some(args.points.clone());
    println!("{report}");
    if let Some(json) = &args.json {
        report.write_json(json)?;
        println!("wrote {}", json.display());
    }
    Ok(())
}
