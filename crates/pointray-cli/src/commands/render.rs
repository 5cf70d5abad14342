//! `pointray render`: a scene file or a bare points file to an image, with optional AOVs, or
//! to a turntable of frames orbiting it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};
use pointray_denoise::{DenoiseSettings, denoise};
use pointray_io::MemoryBudget;
use pointray_render::missing_tiles;
use pointray_scene::image_output::{AovSelection, check_image_outputs, write_image};
use pointray_scene::load::{LoadOptions, LoadedScene, load_scene_file};
use pointray_scene::{
    BufferLayout, HotRecords, Integrator, PatchAcceptance, RenderSetting, RenderSettings, orbit_camera,
};
use pointray_vulkan::TileResidency;

use crate::backend::{BackendArgs, open_backend};
use crate::progress::PrepBar;
use crate::scene_input::SceneInputArgs;
use crate::setting_flag::setting_flag;

/// Render a scene (TOML) or a points file to PNG (8-bit sRGB) or EXR (linear float).
#[derive(Args)]
pub struct RenderArgs {
    /// A scene file (`.toml`), or a points file, shown framed on a floor with one light.
    scene: PathBuf,
    /// The image to write; `.png` or `.exr`. With `--turntable`, frames are numbered after it:
    /// `out.png` gives `out-0000.png`, `out-0001.png`, ...
    #[arg(short, long)]
    output: PathBuf,
    /// Render this many frames, the camera orbiting its look-at point once about its up axis.
    #[arg(long, value_name = "FRAMES", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    turntable: Option<u32>,
    #[arg(long, value_parser = setting_flag(RenderSetting::Width))]
    width: Option<u32>,
    #[arg(long, value_parser = setting_flag(RenderSetting::Height))]
    height: Option<u32>,
    /// Samples per pixel (jittered supersampling).
    #[arg(long, value_parser = setting_flag(RenderSetting::SamplesPerPixel))]
    spp: Option<u32>,
    /// Ray depth: 1 = primary only, 2 = one reflection bounce (the paper's setting); for the
    /// path integrator, path segments (2 = direct light only).
    #[arg(long, value_parser = setting_flag(RenderSetting::MaxDepth))]
    max_depth: Option<u32>,
    /// `whitted` (Phong, hard shadows, mirror reflections) or `path` (path tracing with the
    /// materials' BSDFs, area lights and the sky).
    #[arg(long)]
    integrator: Option<Integrator>,
    /// The path integrator's random seed: the same seed gives the same image.
    #[arg(long)]
    seed: Option<u32>,
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
    /// Consecutive patches one box of the GPU's bottom levels bounds (Vulkan only; default:
    /// the scene file's `patches_per_box`, else 1, or 4 where the scene does not fit the
    /// GPU's memory with 1): more make a smaller BVH and slower frames.
    #[arg(long, value_parser = setting_flag(RenderSetting::PatchesPerBox))]
    patches_per_box: Option<u32>,
    /// The point sets' hot records on the GPU: `packed` (32 bytes a patch, decoded on every
    /// intersection call) or `unpacked` (64, read as they are; boxes of one patch only).
    /// Default: the scene file's `hot_records`, else unpacked for small point sets where the
    /// scene fits the GPU's memory so, packed otherwise (Vulkan only).
    #[arg(long)]
    hot_records: Option<HotRecords>,
    #[command(flatten)]
    backend: BackendArgs,
    /// Also write depth, normal, instance id, primitive id and hit mask next to the image.
    #[arg(long)]
    aovs: bool,
    /// Filter the noise out of a preview of few samples (an edge-aware à-trous filter guided
    /// by the albedo, normal, depth and id AOVs); the AOVs are written unfiltered.
    #[arg(long)]
    denoise: bool,
    #[command(flatten)]
    input: SceneInputArgs,
}

#[derive(Clone, Copy, ValueEnum)]
enum Buffers {
    Split,
    Combined,
}

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let file = args.input.scene_file(&args.scene)?;
    let settings = apply_flags(&args, file.render_settings()?);
    let aovs = if args.aovs { AovSelection::ALL } else { AovSelection::default() };
    let outputs = output_paths(&args.output, args.turntable);
    for output in &outputs {
        check_image_outputs(output, &aovs, &file.input_files())?;
    }
    settings.check_memory(&MemoryBudget::of_this_machine()).map_err(anyhow::Error::msg)?;
    let cache_dir = cache_dir_for(&args.output);
    let bar = PrepBar::default();
    let options = LoadOptions { cache_dir: Some(&cache_dir), progress: &bar, ..LoadOptions::default() };
    let started = Instant::now();
    let LoadedScene { scene, space, .. } = load_scene_file(&file, &options)?;
    println!("loaded {} in {:.2?}", args.scene.display(), started.elapsed());
    let started = Instant::now();
    let backend = open_backend(args.backend.backend, &args.backend.device, args.backend.gpu_memory.budget)?;
    println!("backend: {} (opened in {:.2?})", backend.describe(), started.elapsed());
    let start = scene.camera;
    let started = Instant::now();
    let mut ready = backend.prepare(&scene, &settings)?;
    println!("prepared the scene in {:.2?}", started.elapsed());
    let frames = outputs.len() as u32;
    for (index, output) in (0..).zip(&outputs) {
        let camera = orbit_camera(&start, index, frames, 360.0);
        ready.set_camera(camera);
        let started = Instant::now();
        if let Some(residency) = ready.stream_tiles(&settings)? {
            report_residency(&residency, started.elapsed());
        }
        let started = Instant::now();
        let mut image = backend.trace(&ready, &settings)?;
        let elapsed = started.elapsed();
        println!("rendered {}x{} in {:.2?}", settings.width, settings.height, elapsed);
        if args.denoise {
            let started = Instant::now();
            image = denoise(&image, &DenoiseSettings::default());
            println!("denoised in {:.2?}", started.elapsed());
        }
        image.scale_depth(space.scale as f32);
        let written = write_image(&image, output, &aovs)?;
        if args.turntable.is_some() {
            let at = space.point_to_file(camera.position.as_dvec3());
            println!("frame {index}: camera at {:.6},{:.6},{:.6}", at.x, at.y, at.z);
        }
        for path in written {
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}

/// The image, or with a turntable of `frames` one numbered image a frame.
fn output_paths(output: &Path, turntable: Option<u32>) -> Vec<PathBuf> {
    let Some(frames) = turntable else { return vec![output.to_path_buf()] };
    let stem = output.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let extension = output.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    (0..frames).map(|index| output.with_file_name(format!("{stem}-{index:04}{extension}"))).collect()
}

fn apply_flags(args: &RenderArgs, mut settings: RenderSettings) -> RenderSettings {
    settings.width = args.width.unwrap_or(settings.width);
    settings.height = args.height.unwrap_or(settings.height);
    settings.samples_per_pixel = args.spp.unwrap_or(settings.samples_per_pixel);
    settings.max_depth = args.max_depth.unwrap_or(settings.max_depth);
    settings.integrator = args.integrator.unwrap_or(settings.integrator);
    settings.seed = args.seed.unwrap_or(settings.seed);
    settings.patches_per_box = args.patches_per_box.or(settings.patches_per_box);
    settings.hot_records = args.hot_records.or(settings.hot_records);
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

/// What a streamed scene holds for this frame, and what the image lacks for it.
fn report_residency(residency: &TileResidency, took: Duration) {
    let mib = |bytes: u64| bytes as f64 / f64::from(1 << 20);
    println!(
        "streamed tiles: {} of {} on the GPU in full and {} coarse ({:.1} of {:.1} MiB), {} in full and {} coarse \
         of the {} in view (loaded {}, evicted {} since the last frame or the scene's preparation; updated in \
         {took:.2?})",
        residency.resident,
        residency.tiles,
        residency.coarse,
        mib(residency.resident_bytes),
        mib(residency.budget_bytes),
        residency.in_view_resident,
        residency.in_view_coarse,
        residency.in_view,
        residency.loaded,
        residency.evicted
    );
    if let Some(missing) = missing_tiles(residency) {
        let severity = if residency.missing_in_view() > 0 { "warning" } else { "note" };
        eprintln!("{severity}: {missing}");
    }
}
