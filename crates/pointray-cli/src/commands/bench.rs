//! `pointray bench`: time a scene file or a suite (`table1`) on the Vulkan renderer, or run
//! the scale suite (`scale`) on either backend.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use pointray_bench::{
    BenchError, BenchOptions, CaseResult, FrameCounts, ResimOptions, ScaleBackend, ScaleOptions, ScaleRow,
    Suite, resim_markdown, run_resimulation as run_resimulation_bench, run_scale, run_scene_file, run_suite,
};
use pointray_io::MemoryBudget;
use pointray_render::{Backend, BackendChoice, DeviceSelector};
use pointray_scene::{HotRecords, Integrator, RenderSetting, RenderSettings, SceneFile};
use pointray_vulkan::VulkanRenderer;

use crate::backend::{GpuMemoryArg, backend_choice, device_options, open_backend};
use crate::environment::data_dir;
use crate::progress::PrepBar;
use crate::setting_flag::setting_flag;

/// Time frames with GPU timestamps: FPS, frame and trace times, rays/s, build costs.
#[derive(Args)]
pub struct BenchArgs {
    /// A scene file (.toml), a suite file (bench/suites/*.toml), `table1`, `scale` (1M to
    /// 1B points sampled on the dragon: prep, memory, store, load and FPS; give it --cache),
    /// or `resim` (a real Ouster sweep re-simulated on the GPU in a map of its neighbours:
    /// sweeps per second, checked against the CPU and the real sweep).
    target: String,
    /// Timed frames per case (`resim`: timed sweeps).
    #[arg(long, default_value_t = 100)]
    frames: u32,
    /// Untimed frames before the timed ones, repeated until at least 0.5 s has passed.
    #[arg(long, default_value_t = 10)]
    warmup: u32,
    /// Replace every size (both flags are needed).
    #[arg(long, requires = "height", value_parser = setting_flag(RenderSetting::Width))]
    width: Option<u32>,
    #[arg(long, requires = "width", value_parser = setting_flag(RenderSetting::Height))]
    height: Option<u32>,
    /// Replace every scene's integrator: `whitted` or `path` (with the scene's max_depth and
    /// samples per pixel; a frame of spp 1 is one sample a pixel, so FPS is spp/s).
    #[arg(long)]
    integrator: Option<Integrator>,
    /// Replace every scene's patches a box of the GPU's bottom levels (1: a box per patch;
    /// default: the scene's, else 1, or 4 where the scene does not fit the GPU's memory).
    #[arg(long, value_parser = setting_flag(RenderSetting::PatchesPerBox))]
    patches_per_box: Option<u32>,
    /// Replace every scene's hot records on the GPU: `packed` or `unpacked` (default: the
    /// scene's, else unpacked for small point sets where the scene fits the GPU's memory so).
    #[arg(long)]
    hot_records: Option<HotRecords>,
    /// Only these models of the suite (repeatable).
    #[arg(long = "model")]
    models: Vec<String>,
    /// Also time the ablations (BLAS layout, buffers, box kind, acceptance test).
    #[arg(long)]
    ablations: bool,
    /// Skip the mesh twin of each model (the limit).
    #[arg(long)]
    no_limit: bool,
    /// The data folder (default: POINTRAY_DATA, else the checkout's data/).
    #[arg(long)]
    data: Option<PathBuf>,
    /// Where stand-ins and prepped point sets are cached. `scale` writes gigabytes there and
    /// refuses a folder inside a git checkout.
    #[arg(long, default_value = ".pointray-cache/bench")]
    cache: PathBuf,
    /// `scale` only: the renderer; `auto` takes a hardware ray-tracing GPU, else the CPU.
    #[arg(long, default_value = "auto", value_parser = backend_choice())]
    backend: BackendChoice,
    /// `scale` only: the rungs to run, as point counts, e.g. `1M,30M,500M` (default: 1M, 10M,
    /// 100M, 300M and 1B; a rung that does not fit the machine is skipped with the reason).
    #[arg(long, value_delimiter = ',')]
    rungs: Vec<String>,
    /// `scale` only: where prep in tiles sorts a rung's points (default: the cache folder),
    /// such as /dev/shm where the cache's disk cannot hold them beside the points and store.
    #[arg(long, value_name = "DIR")]
    scratch: Option<PathBuf>,
    #[arg(long)]
    json: Option<PathBuf>,
    #[arg(long)]
    markdown: Option<PathBuf>,
    /// Vulkan device: `auto`, an index from `pointray devices`, or part of its name.
    #[arg(long, default_value = "auto")]
    device: DeviceSelector,
    #[command(flatten)]
    gpu_memory: GpuMemoryArg,
}

/// What `bench` times: a suite of models, or one scene file.
enum Target {
    Suite(Suite),
    Scene(SceneFile),
}

impl Target {
    fn read(target: &str) -> anyhow::Result<Self> {
        if target == "table1" {
            return Ok(Self::Suite(Suite::table1()?));
        }
        let path = PathBuf::from(target);
        pointray_io::ensure_readable_file(&path)?;
        let text = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
        // A suite lists models; anything else is a scene file, whose reader also names the
        // file and line of a syntax error.
        let lists_models = text.parse::<toml::Table>().is_ok_and(|table| table.contains_key("models"));
        Ok(if lists_models {
            Self::Suite(Suite::parse(&text, &path)?)
        } else {
            Self::Scene(SceneFile::parse(&text, &path)?)
        })
    }

    /// Every file the run reads; the reports must not replace any of them.
    fn input_files(&self, data: &Path) -> Vec<PathBuf> {
        match self {
            Self::Suite(suite) => std::iter::once(suite.path.clone())
                .chain(suite.models.iter().flat_map(|model| model.input_files(data)))
                .collect(),
            Self::Scene(file) => file.input_files(),
        }
    }
}

fn print_case(case: &CaseResult) {
    let paper = case.paper_fps.map(|p| format!(" (paper {p:.0}, x{:.2})", case.fps / p)).unwrap_or_default();
    println!(
        "{} {}x{} {}: {:.3} ms/frame (p90 {:.3}), trace {:.3} ms, {:.0} FPS{paper}, {:.2} G rays/s, \
         {:.2} intersection calls/ray",
        case.model,
        case.width,
        case.height,
        case.variant.label(),
        case.frame_median_ms,
        case.frame_p90_ms,
        case.trace_median_ms,
        case.fps,
        case.rays_per_second / 1e9,
        case.intersection_calls_per_ray
    );
}

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    anyhow::ensure!(args.frames > 0, "--frames must be at least 1");
    if args.target == "scale" {
        return run_scale_suite(&args);
    }
    if args.target == "resim" {
        return run_resimulation(&args);
    }
    anyhow::ensure!(args.backend != BackendChoice::Cpu, "only the scale suite runs on the CPU backend");
    let data = args.data.clone().unwrap_or_else(data_dir);
    let target = Target::read(&args.target)?;
    let outputs: Vec<PathBuf> = args.json.iter().chain(&args.markdown).cloned().collect();
    pointray_io::ensure_outputs_spare_inputs(&target.input_files(&data), &outputs)?;
    if let Some((width, height)) = args.width.zip(args.height) {
        let size = RenderSettings { width, height, ..RenderSettings::default() };
        size.check_memory(&MemoryBudget::of_this_machine()).map_err(anyhow::Error::msg)?;
    }
    let device_options = device_options(args.gpu_memory.budget);
    let renderer = Backend::open_vulkan(&args.device, device_options)?;
    println!("device: {}", renderer.device_info());
    let reordering = (args.ablations && renderer.device_info().hit_reordering)
        .then(|| VulkanRenderer::with_hit_reordering(args.device.clone(), device_options))
        .transpose()
        .context("opening a second renderer with hit reordering")?;
    let options = BenchOptions {
        data,
        cache: args.cache.clone(),
        frames: FrameCounts { warmup: args.warmup, timed: args.frames },
        size: args.width.zip(args.height),
        integrator: args.integrator,
        patches_per_box: args.patches_per_box,
        hot_records: args.hot_records,
        limit: !args.no_limit,
        ablations: args.ablations,
        reordering: reordering.as_ref(),
        models: args.models.clone(),
        on_case: &print_case,
    };
    let report = match &target {
        Target::Suite(suite) => run_suite(&renderer, suite, &options)?,
        Target::Scene(file) => run_scene_file(&renderer, &file.path, &options)?,
    };
    emit(
        &args,
        &|path| pointray_bench::write_json(&report, path),
        &pointray_bench::markdown::markdown(&report),
    )
}

/// Writes the report where asked (`write_json`, its `markdown`), else prints the markdown.
fn emit(
    args: &BenchArgs,
    write_json: &dyn Fn(&Path) -> Result<(), BenchError>,
    markdown: &str,
) -> anyhow::Result<()> {
    if let Some(path) = &args.json {
        write_json(path)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.markdown {
        pointray_bench::write_text(markdown, path)?;
        println!("wrote {}", path.display());
    }
    if args.json.is_none() && args.markdown.is_none() {
        print!("{markdown}");
    }
    Ok(())
}

fn print_row(row: &ScaleRow) {
    println!("{}", row.summary());
}

fn run_scale_suite(args: &BenchArgs) -> anyhow::Result<()> {
    let backend = open_backend(args.backend, &args.device, args.gpu_memory.budget)?;
    let scale_backend = ScaleBackend(&backend);
    println!("backend: {}", scale_backend.describe());
    let progress = PrepBar::default();
    let options = ScaleOptions {
        data: args.data.clone().unwrap_or_else(data_dir),
        cache: args.cache.clone(),
        scratch: args.scratch.clone(),
        rungs: pointray_bench::scale::chosen_rungs(&args.rungs).map_err(anyhow::Error::msg)?,
        sizes: pointray_bench::scale::SCALE_SIZES.to_vec(),
        frames: FrameCounts { warmup: args.warmup, timed: args.frames },
        patches_per_box: args.patches_per_box,
        hot_records: args.hot_records,
        progress: &progress,
        on_row: &print_row,
    };
    let report = run_scale(scale_backend, &options)?;
    emit(args, &|path| pointray_bench::write_json(&report, path), &pointray_bench::scale_markdown(&report))
}

fn run_resimulation(args: &BenchArgs) -> anyhow::Result<()> {
    let outputs: Vec<PathBuf> = args.json.iter().chain(&args.markdown).cloned().collect();
    pointray_io::ensure_outputs_spare_inputs(&[], &outputs)?;
    let renderer = Backend::open_vulkan(&args.device, device_options(args.gpu_memory.budget))?;
    println!("device: {}", renderer.device_info());
    let options = ResimOptions {
        data: args.data.clone().unwrap_or_else(data_dir),
        sweeps: FrameCounts { warmup: args.warmup, timed: args.frames },
    };
    let report = run_resimulation_bench(&renderer, &options)?;
    emit(args, &|path| pointray_bench::write_json(&report, path), &resim_markdown(&report))
}
