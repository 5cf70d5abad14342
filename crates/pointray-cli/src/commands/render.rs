//! `pointray render`: a scene file to an image, with optional AOVs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use pointray_io::MemoryBudget;
use pointray_scene::frame_output::{AovSelection, check_frame_outputs, write_frame};
use pointray_scene::load::{LoadOptions, LoadedScene, load_scene_file};
use pointray_scene::{BufferLayout, PatchAcceptance, RenderSetting, RenderSettings, SceneFile};

use crate::backend::{Backend, BackendArgs};
use crate::columns_arg::ColumnsArg;
use crate::progress::PrepBar;
use crate::setting_flag::setting_flag;

/// Render a scene (TOML) to PNG (8-bit sRGB) or EXR (linear float).
#[derive(Args)]
pub struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// The image to write; `.png` or `.exr`.
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, value_parser = setting_flag(RenderSetting::Width))]
    width: Option<u32>,
    #[arg(long, value_parser = setting_flag(RenderSetting::Height))]
    height: Option<u32>,
    /// Samples per pixel (jittered supersampling).
    #[arg(long, value_parser = setting_flag(RenderSetting::SamplesPerPixel))]
    spp: Option<u32>,
    /// Ray depth: 1 = primary only, 2 = one reflection bounce (the paper's setting).
    #[arg(long, value_parser = setting_flag(RenderSetting::MaxDepth))]
    max_depth: Option<u32>,
    /// Turn shadow rays off.
    #[arg(long)]
    no_shadows: bool,
    /// Which hits on a patch count: `box` (inside its box, the paper) or `disk` (also over
    /// its support).
    #[arg(long, default_value = "disk")]
    acceptance: PatchAcceptance,
    /// Per-patch data in split hot/cold buffers or one combined buffer (Vulkan only).
    #[arg(long, value_enum, default_value_t = Buffers::Split)]
    buffers: Buffers,
    #[command(flatten)]
    backend: BackendArgs,
    /// Also write depth, normal, instance id, primitive id and hit mask next to the image.
    #[arg(long)]
    aovs: bool,
    #[command(flatten)]
    columns: ColumnsArg,
}

#[derive(Clone, Copy, ValueEnum)]
enum Buffers {
    Split,
    Combined,
}

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let file = args.columns.apply_to(SceneFile::read(&args.scene)?);
    let settings = apply_flags(&args, file.render_settings()?);
    let aovs = if args.aovs { AovSelection::ALL } else { AovSelection::default() };
    check_frame_outputs(&args.output, &aovs, &file.input_files())?;
    settings.check_memory(&MemoryBudget::of_this_machine()).map_err(anyhow::Error::msg)?;
    let cache_dir = cache_dir_for(&args.output);
    let bar = PrepBar::default();
    let options = LoadOptions { cache_dir: Some(&cache_dir), progress: &bar };
    let LoadedScene { scene, frame: render_frame, .. } = load_scene_file(&file, &options)?;
    let backend = Backend::open(args.backend.backend, &args.backend.device)?;
    println!("backend: {}", backend.describe());
    let started = Instant::now();
    let mut frame = backend.render(&scene, &settings)?;
    let elapsed = started.elapsed();
    frame.scale_depth(render_frame.scale as f32);
    let written = write_frame(&frame, &args.output, &aovs)?;
    println!("rendered {}x{} in {:.2?}", settings.width, settings.height, elapsed);
    for path in written {
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn apply_flags(args: &RenderArgs, mut settings: RenderSettings) -> RenderSettings {
    settings.width = args.width.unwrap_or(settings.width);
    settings.height = args.height.unwrap_or(settings.height);
    settings.samples_per_pixel = args.spp.unwrap_or(settings.samples_per_pixel);
    settings.max_depth = args.max_depth.unwrap_or(settings.max_depth);
    settings.shadows &= !args.no_shadows;
    settings.acceptance = args.acceptance;
    settings.buffer_layout = match args.buffers {
        Buffers::Split => BufferLayout::Split,
        Buffers::Combined => BufferLayout::Combined,
    };
    settings
}

/// Prepared point sets are cached beside the output, never beside the (maybe read-only) input.
fn cache_dir_for(output: &Path) -> PathBuf {
    let parent = output.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    parent.join(".pointray-cache")
}
