//! The `scale` suite: clouds of 1M to 1B points sampled on the dragon mesh (labelled
//! stand-ins), each generated once into the cache, then prepped, stored, loaded and rendered
//! on a reflective floor with shadows. Rungs that do not fit the machine are skipped with
//! the reason (`scale_fit.rs`).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use pointray_io::{MemoryBudget, PointStream};
use pointray_patches::PrepSettings;
use pointray_patches::patch_store;
use pointray_scene::{HotRecords, RenderSettings, RenderedImage};
use pointray_surface::peak_memory::StagePeaks;
use pointray_surface::prep_memory::{PrepRoute, prep_route};
use pointray_surface::tiles::streamed_prep::prep_streamed;
use pointray_surface::tiles::streamed_tiles::TileCount;
use pointray_surface::{PrepProgress, prep_owned};

use crate::data::ensure_cache_dir;
use crate::error::BenchError;
use crate::measure::FrameCounts;
use crate::model_scene::load_with_model;
use crate::scale_fit::MachineLimits;
use crate::scale_render::ScaleBackend;
use crate::scale_report::{RungMeasurement, RungOutcome, ScaleReport, ScaleRow, SizeFps};
use crate::stand_in::{stand_in_label, stand_in_path, stand_in_points};
use crate::suite::StandInSpec;

/// The rungs, smallest first.
pub const RUNGS: [(&str, u64); 5] = [
    ("1M", 1_000_000),
    ("10M", 10_000_000),
    ("100M", 100_000_000),
    ("300M", 300_000_000),
    ("1B", 1_000_000_000),
];

/// The mesh the stand-ins are sampled on, in the data folder, and their seed.
pub const SCALE_MESH: &str = "meshes/dragon_res2.ply";
pub const SCALE_SEED: u64 = 1;

/// The sizes each rung is rendered at.
pub const SCALE_SIZES: [(u32, u32); 2] = [(1920, 1080), (640, 640)];

/// One rung: its label and how many points it samples.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rung {
    pub label: String,
    pub points: u64,
}

/// The setting: the dragon on a reflective floor under one light (the paper's figures).
const SCENE: &str = include_str!("../../../scenes/dragon_floor.toml");

pub struct ScaleOptions<'a> {
    pub data: PathBuf,
    /// Where the points files, patch stores and scene files go; never the repository.
    pub cache: PathBuf,
    /// Where prep in tiles sorts the points; the cache folder when `None`.
    pub scratch: Option<PathBuf>,
    /// The rungs to run (`chosen_rungs`) and the sizes to render each at (`SCALE_SIZES`).
    pub rungs: Vec<Rung>,
    pub sizes: Vec<(u32, u32)>,
    pub frames: FrameCounts,
    /// Replaces the scene's patches a box (`RenderSettings::patches_per_box`).
    pub patches_per_box: Option<u32>,
    /// Replaces the scene's hot records (`RenderSettings::hot_records`).
    pub hot_records: Option<HotRecords>,
    /// Told about prep's stages (a progress bar).
    pub progress: &'a dyn PrepProgress,
    /// Called with each row as it completes.
    pub on_row: &'a dyn Fn(&ScaleRow),
}

/// The rungs named by `labels` (all of `RUNGS` when empty): point counts, each a whole number
/// with an optional `K`, `M` or `B` (thousands, millions, billions), such as `30M` or `2B`.
pub fn chosen_rungs(labels: &[String]) -> Result<Vec<Rung>, String> {
    if labels.is_empty() {
        return Ok(RUNGS.into_iter().map(|(label, points)| Rung { label: label.into(), points }).collect());
    }
    labels.iter().map(|label| rung_of(label)).collect()
}

/// The rung of `label`, labelled as the default rungs are (`30m` becomes `30M`).
fn rung_of(label: &str) -> Result<Rung, String> {
    let text = label.trim();
    let digits = text.find(|c: char| !c.is_ascii_digit()).unwrap_or(text.len());
    let (number, suffix) = text.split_at(digits);
    let scale = match suffix.to_ascii_uppercase().as_str() {
        "" => 1,
        "K" => 1_000,
        "M" => 1_000_000,
        "B" => 1_000_000_000,
        _ => 0,
    };
    let points = number.parse::<u64>().ok().and_then(|n| n.checked_mul(scale)).filter(|&n| n > 0);
    let points = points.ok_or_else(|| {
        format!("no scale rung `{label}`: a rung is a point count above 0, such as 300000, 250K, 30M or 2B")
    })?;
    Ok(Rung { label: format!("{number}{}", suffix.to_ascii_uppercase()), points })
}

pub fn run_scale(backend: ScaleBackend, options: &ScaleOptions) -> Result<ScaleReport, BenchError> {
    refuse_repository(&options.cache)?;
    ensure_cache_dir(&options.cache)?;
    let mut rows = Vec::new();
    let mut first_image = None;
    for Rung { label, points } in options.rungs.iter().cloned() {
        let spec = StandInSpec { mesh: SCALE_MESH.into(), count: points as usize, seed: SCALE_SEED };
        let cached = stand_in_path(&options.data, &spec, &options.cache)
            .ok()
            .and_then(|path| std::fs::metadata(path).ok())
            .map_or(0, |metadata| metadata.len());
        let limits =
            MachineLimits::now((&options.cache, options.scratch.as_deref()), backend.device_limits());
        let outcome = match limits.why_not(points, cached) {
            Some(reason) => RungOutcome::Skipped { reason },
            None => RungOutcome::Measured(measure_rung(backend, &label, &spec, options, &mut first_image)?),
        };
        let row = ScaleRow { label, points, stand_in: stand_in_label(&spec), outcome };
        (options.on_row)(&row);
        rows.push(row);
    }
    Ok(ScaleReport { backend: backend.describe(), timing: backend.timing().into(), rows })
}

/// The size of the frame each rung's image is compared at.
const CHECK_SIZE: (u32, u32) = (480, 270);

/// Generates (once), preps, stores, loads and renders one rung, and compares its image with
/// `first_image`, the first measured rung's (which it becomes where there is none yet).
fn measure_rung(
    backend: ScaleBackend,
    label: &str,
    spec: &StandInSpec,
    options: &ScaleOptions,
    first_image: &mut Option<RenderedImage>,
) -> Result<RungMeasurement, BenchError> {
    let points_file = stand_in_points(&options.data, spec, &options.cache)?;
    let store = options.cache.join(format!("scale-{label}.patches"));
    let scratch = options.scratch.as_deref().unwrap_or(&options.cache);
    let prepped = prep_rung(label, &points_file, (&store, scratch), options.progress)?;
    let store_bytes = std::fs::metadata(&store).map_or(0, |metadata| metadata.len());
    let started = Instant::now();
    let table: toml::Table = toml::from_str(SCENE).map_err(|e| BenchError::ParseSuite {
        path: PathBuf::from("scenes/dragon_floor.toml"),
        message: e.to_string(),
    })?;
    let scene_path = options.cache.join(format!("scale-{label}.toml"));
    let loaded = load_with_model(label, &table, "points", &store, &scene_path, &options.cache)?;
    let base = RenderSettings {
        patches_per_box: options.patches_per_box.or(loaded.settings.patches_per_box),
        hot_records: options.hot_records.or(loaded.settings.hot_records),
        ..loaded.settings
    };
    let (mut ready, costs) = backend.prepare(&loaded.scene, &base, label)?;
    let load = started.elapsed();
    let fps = options
        .sizes
        .iter()
        .map(|&(width, height)| {
            let settings = RenderSettings { width, height, ..base };
            let case = format!("{label} {width}x{height}");
            backend.stream_tiles(&mut ready, &settings, &case)?;
            let frame = backend.frame_time(&ready, &settings, options.frames, &case)?;
            Ok(SizeFps { width, height, fps: 1.0 / frame.as_secs_f64(), frame_ms: frame.as_secs_f64() * 1e3 })
        })
        .collect::<Result<_, BenchError>>()?;
    let check = RenderSettings { width: CHECK_SIZE.0, height: CHECK_SIZE.1, ..base };
    backend.stream_tiles(&mut ready, &check, label)?;
    let image = backend.image(&ready, &check, label)?;
    let image_psnr_db = first_image.as_ref().map(|first| image.color_psnr(first));
    first_image.get_or_insert(image);
    let points = spec.count as f64;
    Ok(RungMeasurement {
        prep_route: prepped.route.into(),
        read_seconds: prepped.read.as_secs_f64(),
        prep_seconds: prepped.prep.as_secs_f64(),
        prep_points_per_second: points / prepped.prep.as_secs_f64(),
        prep_peak_rss_bytes: prepped.peak,
        store_bytes,
        store_write_seconds: prepped.store_write.as_secs_f64(),
        load_seconds: load.as_secs_f64(),
        blas_build_seconds: costs.blas.as_secs_f64(),
        bottom_levels: costs.tiles,
        patches_per_box: costs.patches_per_box,
        hot_records: costs.hot_records,
        gpu_bytes_per_point: costs.gpu_bytes.map(|bytes| bytes as f64 / points),
        gpu_build_peak_bytes_per_point: costs.gpu_peak_bytes.map(|bytes| bytes as f64 / points),
        fps,
        image_psnr_db,
    })
}

/// How a rung's prep went.
struct RungPrep {
    route: &'static str,
    read: Duration,
    prep: Duration,
    store_write: Duration,
    peak: Option<u64>,
}

/// Preps `points_file` into the store `store` as `pointray prep` does with its default
/// budget: in memory when a single pass fits, else streamed in tiles.
fn prep_rung(
    label: &str,
    points_file: &Path,
    (store, scratch): (&Path, &Path),
    progress: &dyn PrepProgress,
) -> Result<RungPrep, BenchError> {
    let settings = PrepSettings::default();
    let budget = MemoryBudget::half_of_this_machine();
    let mut stream = PointStream::open(points_file, None, budget)?;
    let route = prep_route(stream.len(), &settings, stream.attribute_bytes_per_point(), budget);
    if route == PrepRoute::Streamed {
        let peaks = StagePeaks::new(progress);
        let count = (TileCount::AtLeast(1), budget);
        let (prepped, prep) =
            timed(|| prep_streamed(&mut stream, &settings, count, (store, scratch), &peaks));
        prepped.map_err(|source| BenchError::StreamedPrep { case: label.into(), source })?;
        let (read, store_write) = (Duration::ZERO, Duration::ZERO);
        return Ok(RungPrep { route: "streamed", read, prep, store_write, peak: peaks.overall() });
    }
    drop(stream);
    let (cloud, read) = timed(|| pointray_io::formats::read_point_cloud(points_file));
    let cloud = cloud?;
    let peaks = StagePeaks::new(progress);
    let (prepped, prep) = timed(|| prep_owned(cloud, &settings, &peaks));
    let (patches, _) = prepped.map_err(|source| BenchError::Prep { case: label.into(), source })?;
    let (written, store_write) = timed(|| patch_store::write(store, &patches));
    written.map_err(|source| BenchError::Store { case: label.into(), source })?;
    Ok(RungPrep { route: "in memory", read, prep, store_write, peak: peaks.overall() })
}

fn timed<T>(work: impl FnOnce() -> T) -> (T, Duration) {
    let started = Instant::now();
    let result = work();
    (result, started.elapsed())
}

/// The suite writes gigabytes: it refuses a cache folder inside a git checkout.
fn refuse_repository(cache: &Path) -> Result<(), BenchError> {
    let absolute = std::path::absolute(cache).unwrap_or(cache.to_path_buf());
    match absolute.ancestors().find(|folder| folder.join(".git").exists()) {
        Some(checkout) => {
            Err(BenchError::CacheInRepository { path: cache.to_path_buf(), checkout: checkout.to_path_buf() })
        }
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rungs(labels: &[&str]) -> Result<Vec<(String, u64)>, String> {
        let labels: Vec<String> = labels.iter().map(|label| label.to_string()).collect();
        Ok(chosen_rungs(&labels)?.into_iter().map(|rung| (rung.label, rung.points)).collect())
    }

    #[test]
    fn rungs_are_any_point_count_with_a_suffix_or_none() {
        let chosen = rungs(&["30m", " 2B", "250K", "1234"]).unwrap();
        let expected = [("30M", 30_000_000), ("2B", 2_000_000_000), ("250K", 250_000), ("1234", 1234)];
        assert_eq!(chosen, expected.map(|(label, points)| (label.to_string(), points)));
        assert_eq!(rungs(&[]).unwrap().len(), RUNGS.len(), "no label runs the default rungs");
    }

    #[test]
    fn a_rung_that_is_no_count_is_refused_by_name() {
        for label in ["", "0M", "M", "30G", "1.5B", "-3M", "99999999999B"] {
            let error = rungs(&[label]).expect_err(label);
            assert!(error.contains(&format!("`{label}`")), "{error}");
        }
    }
}
