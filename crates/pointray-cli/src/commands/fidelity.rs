//! `pointray fidelity`: a points file against the mesh it came from, as numbers.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::Context;
use clap::Args;
use glam::{DVec3, Vec3};
use pointray_fidelity::view_images::is_view_image;
use pointray_fidelity::view_placement::validate_setting;
use pointray_fidelity::{FidelityOptions, ImageRenderer, RenderError, SensorPose, measure_fidelity};
use pointray_io::MemoryBudget;
use pointray_scene::{RenderSetting, RenderSettings, RenderedImage, Scene};

use crate::backend::{backend_choice, open_backend};
use crate::patch_args::PatchArgs;
use crate::setting_flag::setting_flag;
use crate::view_args::ViewArgs;
use pointray_render::{Backend, BackendChoice, DeviceSelector, missing_tiles};

/// Render the points' patches and the mesh from the same cameras and report holes, false
/// surfaces, depth and normal error (against the mesh's interpolated vertex normals) and
/// PSNR, as a table (and JSON with `--json`).
#[derive(Args)]
pub struct FidelityArgs {
    /// The points file (any format `prep` reads), in the mesh's coordinates.
    points: PathBuf,
    /// The mesh the points were sampled or scanned from (PLY or OBJ).
    mesh: PathBuf,
    #[command(flatten)]
    views: ViewArgs,
    /// Images of this many pixels a side (sensor views: this wide).
    #[arg(long, default_value_t = 512, value_parser = setting_flag(RenderSetting::Width))]
    size: u32,
    #[command(flatten)]
    patches: PatchArgs,
    /// Also write the report as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write each view's mesh, points, difference and normal-error images into this folder
    /// (made if missing): holes red (dark red where the sensor never looked), false surface
    /// blue, normal error from black (0°) through red (15°) to yellow (30° or more).
    #[arg(long, value_name = "DIR")]
    images: Option<PathBuf>,
    #[arg(long, default_value = "cpu", value_parser = backend_choice())]
    backend: BackendChoice,
    /// Vulkan device: `auto`, an index from `pointray devices`, or part of its name.
    #[arg(long, default_value = "auto")]
    device: DeviceSelector,
}

/// The CLI's backend choice (CPU or Vulkan) as the fidelity crate's renderer.
struct ChosenBackend(Backend);

impl ImageRenderer for ChosenBackend {
    fn name(&self) -> String {
        self.0.describe()
    }

    /// Refuses a streamed scene short of any tile: what it lacks, or the shadows and
    /// reflections of what it lacks, would count as the points' error.
    fn render(&self, scene: &Scene, settings: &RenderSettings) -> Result<RenderedImage, RenderError> {
        let (image, residency) = self.0.render(scene, settings)?;
        match residency.as_ref().and_then(missing_tiles) {
            Some(missing) => {
                Err(format!("measuring fidelity needs every tile on the GPU, but {missing}").into())
            }
            None => Ok(image),
        }
    }
}

/// The centre of the bounds of `positions`; `None` when there are none.
fn bounds_centre(positions: &[DVec3]) -> Option<Vec3> {
    let first = *positions.first()?;
    let (low, high) = positions.iter().fold((first, first), |(low, high), &p| (low.min(p), high.max(p)));
    Some(((low + high) * 0.5).as_vec3())
}

pub fn run(args: FidelityArgs) -> anyhow::Result<()> {
    let inputs = [args.points.clone(), args.mesh.clone()];
    pointray_io::ensure_outputs_spare_inputs(&inputs, args.json.as_slice())?;
    let mut options = FidelityOptions::with_views(args.views.specs()?, args.size, args.patches.acceptance());
    options.up = args.views.up;
    options.fov_degrees = args.views.fov;
    options.image_folder = args.images.clone();
    // Before the prep, which can take minutes.
    validate_setting(options.up, options.fov_degrees, options.size)?;
    let size = RenderSettings { width: args.size, height: args.size, ..RenderSettings::default() };
    size.check_memory(&MemoryBudget::of_this_machine()).map_err(anyhow::Error::msg)?;
    let prep_settings = args.patches.prep_settings()?;
    if let Some(folder) = &args.images {
        check_image_folder(folder, &inputs)?;
    }
    let mesh = pointray_io::formats::read_triangle_mesh(&args.mesh)?;
    let cloud = args.patches.read(&args.points)?;
    if args.views.wants_sensor() {
        let pose = SensorPose::of_cloud(&cloud, options.up, args.patches.sensor())
            .with_context(|| format!("{}: placing the sensor views", args.points.display()))?;
        options.sensor = Some(pose);
    }
    options.points_centre = bounds_centre(&cloud.positions);
    let (patches, _) = args.patches.prep(&args.points, &cloud, &prep_settings)?;
    drop(cloud);
    let backend = ChosenBackend(open_backend(args.backend, &args.device, None)?);
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

/// Makes the folder for `--images` and refuses it when an image it would write is one of the
/// inputs (only existing files can be).
fn check_image_folder(folder: &Path, inputs: &[PathBuf]) -> anyhow::Result<()> {
    std::fs::create_dir_all(folder).map_err(|e| pointray_io::IoError::os(folder, e))?;
    let existing: Vec<PathBuf> = std::fs::read_dir(folder)
        .map_err(|e| pointray_io::IoError::os(folder, e))?
        .flatten()
        .map(|entry| entry.path())
        .filter(|path| is_view_image(path))
        .collect();
    Ok(pointray_io::ensure_outputs_spare_inputs(inputs, &existing)?)
}
