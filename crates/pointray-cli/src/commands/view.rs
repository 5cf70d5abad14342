//! `pointray view`: the interactive viewer on a scene file or a bare points file.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use pointray_scene::SceneFile;
use pointray_scene::load::{LoadOptions, LoadedScene, load_scene_file};
use pointray_viewer::{RenderBackend, Script, ViewerOptions, run_viewer};
use pointray_vulkan::validation_requested_by_env;

use crate::backend::{BackendArgs, BackendChoice};
use crate::columns_arg::ColumnsArg;
use crate::progress::PrepBar;

/// Open a window on a scene (TOML) or a points file, and fly around it.
#[derive(Args)]
pub struct ViewArgs {
    /// A scene file (`.toml`), or a points file shown on a floor with one light.
    scene: PathBuf,
    /// Window size in pixels (defaults: the scene's render size).
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel of the first pass (more accumulate while the view is still).
    #[arg(long)]
    spp: Option<u32>,
    #[command(flatten)]
    backend: BackendArgs,
    /// Wait for the display between frames (FIFO presentation); `V` toggles it.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set)]
    vsync: bool,
    /// Render this many frames along a turntable orbit, then exit.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    frames: Option<u32>,
    /// Degrees the scripted orbit turns over all its frames.
    #[arg(long, default_value_t = 360.0, requires = "frames")]
    arc: f32,
    /// Save the last scripted frame here (`.png` or `.exr`).
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Save every scripted frame into this folder as `frame-NNNNN.png`.
    #[arg(long, requires = "frames")]
    sequence: Option<PathBuf>,
    #[command(flatten)]
    columns: ColumnsArg,
}

pub fn run(args: ViewArgs) -> anyhow::Result<()> {
    let LoadedScene { scene, mut settings, .. } = load(&args.scene, &args.columns)?;
    settings.width = args.width.unwrap_or(settings.width);
    settings.height = args.height.unwrap_or(settings.height);
    settings.samples_per_pixel = args.spp.unwrap_or(settings.samples_per_pixel);
    let script = args.frames.map(|frames| Script {
        frames,
        arc_degrees: args.arc,
        screenshot: args.screenshot.clone(),
        sequence: args.sequence.clone(),
    });
    let backend = match args.backend.backend {
        BackendChoice::Auto => RenderBackend::Auto,
        BackendChoice::Vulkan => RenderBackend::Vulkan,
        BackendChoice::Cpu => RenderBackend::Cpu,
    };
    let options = ViewerOptions {
        backend,
        device: args.backend.device,
        vsync: args.vsync,
        validation: validation_requested_by_env(),
        script,
    };
    let summary = run_viewer(scene, settings, options)?;
    println!("presented {} frames", summary.frames_presented);
    if let Some(path) = &args.screenshot {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// A `.toml` is a scene; anything else is a points file given the default scene. Prepared
/// point sets are cached in `.pointray-cache` in the working directory.
fn load(path: &Path, columns: &ColumnsArg) -> anyhow::Result<LoadedScene> {
    let cache_dir = PathBuf::from(".pointray-cache");
    std::fs::create_dir_all(&cache_dir).with_context(|| format!("creating {}", cache_dir.display()))?;
    let bar = PrepBar::default();
    let options = LoadOptions { cache_dir: Some(&cache_dir), progress: &bar };
    let is_scene = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    let file = if is_scene { SceneFile::read(path)? } else { SceneFile::for_points_file(path) };
    Ok(load_scene_file(&columns.apply_to(file), &options)?)
}
