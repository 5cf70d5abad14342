//! `pointray fidelity`: a points file against the mesh it came from, as numbers (issue 4).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::Context;
use clap::Args;
use pointray_fidelity::{FidelityOptions, FrameRenderer, RenderError, measure_fidelity};
use pointray_io::MemoryBudget;
use pointray_scene::{Frame, PatchAcceptance, RenderSetting, RenderSettings, Scene};
use pointray_surface::input_validation::validate_options;
use pointray_surface::{PatchSet, PrepOptions, PrepParams, prep};
use pointray_vulkan::DeviceSelector;

use crate::backend::{Backend, BackendChoice};
use crate::boxes_arg::Boxes;
use crate::columns_arg::ColumnsArg;
use crate::progress::PrepBar;
use crate::radius_arg::Radius;
use crate::setting_flag::setting_flag;

/// Render the points' patches and the mesh from cameras around the model and report holes,
/// false surfaces, depth and normal error and PSNR, as a table (and JSON with `--json`).
#[derive(Args)]
pub struct FidelityArgs {
    /// The points file (any format `prep` reads), in the mesh's coordinates.
    points: PathBuf,
    /// The mesh the points were sampled from (PLY or OBJ).
    mesh: PathBuf,
    /// Cameras around the model: 6 looks along the axes, more are spread evenly.
    #[arg(long, default_value_t = 6)]
    views: usize,
    /// Square images of this many pixels a side.
    #[arg(long, default_value_t = 512, value_parser = setting_flag(RenderSetting::Width))]
    size: u32,
    /// Neighbours for the support radius and the quadratic fit.
    #[arg(long, default_value_t = 9)]
    k: u32,
    /// Which hits on a patch count: `box` (inside its box, the paper) or `disk` (also over
    /// its support).
    #[arg(long, default_value = "disk")]
    acceptance: PatchAcceptance,
    /// The box around each patch.
    #[arg(long, value_enum, default_value_t = Boxes::Tight)]
    boxes: Boxes,
    /// The support radius: the point's Voronoi cell (the default), the paper's, or adapted
    /// to the local density.
    #[arg(long, value_enum, default_value_t = Radius::Cell)]
    radius: Radius,
    /// How far each patch reaches, as a fraction of the paper's support radius.
    #[arg(long, default_value_t = PrepParams::default().disk_scale)]
    disk_scale: f32,
    /// Also write the report as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = BackendChoice::Cpu)]
    backend: BackendChoice,
    /// Vulkan device: `auto`, an index from `pointray devices`, or part of its name.
    #[arg(long, default_value = "auto")]
    device: DeviceSelector,
    #[command(flatten)]
    columns: ColumnsArg,
}

/// The CLI's backend choice (CPU or Vulkan) as the fidelity crate's renderer.
struct ChosenBackend(Backend);

impl FrameRenderer for ChosenBackend {
    fn name(&self) -> String {
        self.0.describe()
    }

    fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<Frame, RenderError> {
        Ok(self.0.render(scene, settings)?)
    }
}

pub fn run(args: FidelityArgs) -> anyhow::Result<()> {
    let inputs = [args.points.clone(), args.mesh.clone()];
    pointray_io::ensure_outputs_spare_inputs(&inputs, args.json.as_slice())?;
    let options = FidelityOptions::around(args.views, args.size, args.acceptance)?;
    let size = RenderSettings { width: args.size, height: args.size, ..RenderSettings::default() };
    size.check_memory(&MemoryBudget::of_this_machine()).map_err(anyhow::Error::msg)?;
    let prep_options = PrepOptions {
        params: PrepParams {
            k: args.k,
            box_kind: args.boxes.into(),
            disk_scale: args.disk_scale,
            ..PrepParams::default()
        },
        radius_mode: args.radius.into(),
        ..PrepOptions::default()
    };
    validate_options(&prep_options).map_err(crate::commands::prep::flag_error)?;
    let mesh = pointray_io::formats::read_triangle_mesh(&args.mesh)?;
    let patches = prep_points(&args.points, &args.columns, prep_options)?;
    let backend = ChosenBackend(Backend::open(args.backend, &args.device)?);
    println!("backend: {}", backend.name());
    let mut report = measure_fidelity(Arc::new(patches), Arc::new(mesh), &options, &backend)
        .with_context(|| format!("comparing {} against {}", args.points.display(), args.mesh.display()))?;
    report.setup.points_file = Some(args.points.clone());
    report.setup.mesh_file = Some(args.mesh.clone());
    println!("{report}");
    if let Some(json) = &args.json {
        report.write_json(json)?;
        println!("wrote {}", json.display());
    }
    Ok(())
}

fn prep_points(path: &Path, columns: &ColumnsArg, options: PrepOptions) -> anyhow::Result<PatchSet> {
    let cloud = columns.read_point_cloud(path)?;
    let (patches, _) = prep(&cloud, &options, &PrepBar::default())
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(patches)
}
