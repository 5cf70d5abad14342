//! `pointray view`: the interactive viewer on a scene file or a bare points file.

use std::path::{Path, PathBuf};

use clap::Args;
use pointray_io::MemoryBudget;
use pointray_scene::image_output::check_image_outputs;
use pointray_scene::load::{LoadOptions, LoadedScene, load_scene_file};
use pointray_scene::{AovSelection, Integrator, RenderSetting, SceneFile};
use pointray_viewer::{Script, ViewerOptions, run_viewer, sequence_path};

use crate::backend::BackendArgs;
use crate::backend::device_options;
use crate::progress::PrepBar;
use crate::scene_input::SceneInputArgs;
use crate::setting_flag::setting_flag;

/// Open a window on a scene (TOML) or a points file, and fly around it.
#[derive(Args)]
pub struct ViewArgs {
    /// A scene file (`.toml`), or a points file shown on a floor with one light.
    scene: PathBuf,
    /// Window size in pixels (defaults: the scene's render size).
    #[arg(long, value_parser = setting_flag(RenderSetting::Width))]
    width: Option<u32>,
    #[arg(long, value_parser = setting_flag(RenderSetting::Height))]
    height: Option<u32>,
    /// Samples per pixel of the first pass (more accumulate while the view is still).
    #[arg(long, value_parser = setting_flag(RenderSetting::SamplesPerPixel))]
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
    #[arg(long, default_value_t = 360.0, requires = "frames", value_parser = finite_degrees)]
    arc: f32,
    /// Save the last scripted frame here (`.png` or `.exr`).
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Save every scripted frame into this folder as `frame-NNNNN.png`.
    #[arg(long, requires = "frames")]
    sequence: Option<PathBuf>,
    #[command(flatten)]
    input: SceneInputArgs,
}

/// A finite angle: NaN or infinity would put the orbit's camera nowhere and save a black frame.
fn finite_degrees(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(degrees) if degrees.is_finite() => Ok(degrees),
        _ => Err(format!("'{text}' is not a finite number of degrees")),
    }
}

pub fn run(args: ViewArgs) -> anyhow::Result<()> {
    let file = args.input.scene_file(&args.scene)?;
    let mut settings = file.render_settings()?;
    settings.width = args.width.unwrap_or(settings.width);
    settings.height = args.height.unwrap_or(settings.height);
    settings.samples_per_pixel = args.spp.unwrap_or(settings.samples_per_pixel);
    if settings.integrator != Integrator::Whitted {
        // Windows trace with the Whitted pipeline; progressive path tracing in the viewer is
        // yet to come.
        println!("note: the viewer shows the Whitted integrator; `pointray render` path traces this scene");
        settings.integrator = Integrator::Whitted;
    }
    check_outputs(&args, &file.input_files())?;
    settings.check_memory(&MemoryBudget::of_this_machine()).map_err(anyhow::Error::msg)?;
    let LoadedScene { scene, .. } = load(&file)?;
    let script = args.frames.map(|frames| Script {
        frames,
        arc_degrees: args.arc,
        screenshot: args.screenshot.clone(),
        sequence: args.sequence.clone(),
    });
    let options = ViewerOptions {
        backend: args.backend.backend,
        device: args.backend.device,
        device_options: device_options(args.backend.gpu_memory.budget),
        vsync: args.vsync,
        script,
    };
    let summary = run_viewer(scene, settings, options)?;
    println!("presented {} frames", summary.frames_presented);
    if let Some(path) = &args.screenshot {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The screenshot and every frame of the sequence that would replace an existing file, against
/// the scene's inputs, before anything is loaded.
fn check_outputs(args: &ViewArgs, inputs: &[PathBuf]) -> anyhow::Result<()> {
    if let Some(screenshot) = &args.screenshot {
        check_image_outputs(screenshot, &AovSelection::default(), inputs)?;
    }
    if let (Some(dir), Some(frames)) = (&args.sequence, args.frames) {
        if dir.exists() && !dir.is_dir() {
            anyhow::bail!("{}: is not a folder; --sequence names the folder for the frames", dir.display());
        }
        if dir.is_dir() {
            let existing: Vec<PathBuf> = std::fs::read_dir(dir)
                .map_err(|e| pointray_io::IoError::os(dir, e))?
                .flatten()
                .map(|entry| entry.path())
                .filter(|path| is_sequence_frame(dir, path, frames))
                .collect();
            pointray_io::ensure_outputs_spare_inputs(inputs, &existing)?;
        }
    }
    Ok(())
}

/// Whether `path` is one of the `frames` files the sequence writes into `dir`.
fn is_sequence_frame(dir: &Path, path: &Path, frames: u32) -> bool {
    let index = path
        .file_name()
        .and_then(|name| name.to_str())
        .and_then(|name| name.strip_prefix("frame-")?.strip_suffix(".png")?.parse::<u32>().ok());
    index.is_some_and(|index| index < frames && sequence_path(dir, index) == path)
}

/// Prepared point sets are cached in `.pointray-cache` in the working directory.
fn load(file: &SceneFile) -> anyhow::Result<LoadedScene> {
    let cache_dir = PathBuf::from(".pointray-cache");
    let bar = PrepBar::default();
    let options = LoadOptions { cache_dir: Some(&cache_dir), progress: &bar, ..LoadOptions::default() };
    Ok(load_scene_file(file, &options)?)
}
