//! CI smoke test (lavapipe is enough): the table1 suite runs end to end on one small model and
//! its numbers are sane; the GPU ray count is exact where it can be computed by hand; the
//! scale suite runs a small rung on both backends and skips one that cannot fit. It asserts
//! that the benchmark works, not how fast anything is.

use std::path::{Path, PathBuf};

use pointray_bench::scale::Rung;
use pointray_bench::scale_report::{RungMeasurement, RungOutcome};
use pointray_bench::{
    BenchError, BenchOptions, FrameCounts, ScaleBackend, ScaleOptions, ScaleReport, Suite, Variant,
    run_scale, run_scene_file, run_suite, scale_markdown,
};
use pointray_render::Backend;
use pointray_scene::Integrator;
use pointray_surface::NoProgress;
use pointray_vulkan::{DeviceOptions, DeviceSelector, VulkanRenderer};

use pointray_test_support::{data_dir, vulkan_renderer as renderer};

fn options<'a>(data: PathBuf, cache: &Path, size: Option<(u32, u32)>, ablations: bool) -> BenchOptions<'a> {
    BenchOptions {
        data,
        cache: cache.to_path_buf(),
        frames: FrameCounts { warmup: 1, timed: 3 },
        size,
        integrator: None,
        patches_per_box: None,
        hot_records: None,
        limit: true,
        ablations,
        reordering: None,
        models: vec!["Bunny".into()],
        on_case: &|_| {},
    }
}

#[test]
fn table1_bunny_runs_with_limit_and_ablations() {
    let Some(renderer) = renderer() else { return };
    let data = data_dir();
    let cache = tempfile::tempdir().expect("a temporary folder");
    let suite = Suite::table1().expect("the built-in suite parses");
    let report =
        run_suite(&renderer, &suite, &options(data, cache.path(), Some((32, 24)), true)).expect("runs");
    let variants: Vec<Variant> = report.cases.iter().map(|c| c.variant).collect();
    assert_eq!(
        variants,
        [
            Variant::Points,
            Variant::Mesh,
            Variant::CombinedBuffers,
            Variant::BoxAcceptance,
            Variant::AovOutput,
            Variant::PackedRecords,
            Variant::SmallerDisks,
            Variant::PaperRadius,
            Variant::TriangleProxies,
            Variant::GeometryPerAabb,
            Variant::CubeBoxes,
            Variant::PaperConfiguration,
            Variant::SixNeighbours
        ]
    );
    for case in &report.cases {
        assert_eq!((case.width, case.height, case.frames), (32, 24, 3), "{case:?}");
        assert!(case.fps > 0.0 && case.frame_median_ms >= case.trace_median_ms, "{case:?}");
        assert!(case.frame_p90_ms >= case.frame_median_ms, "{case:?}");
        // At least one primary ray per pixel; shadows and the mirror floor add more.
        assert!(case.rays_per_frame > 32 * 24, "{case:?}");
        // Rays meet patch boxes in every point-set case; a mesh, and the patches' triangle
        // proxies, have none to call the intersection shader for.
        let calls = case.intersection_calls_per_ray;
        let triangles = matches!(case.variant, Variant::Mesh | Variant::TriangleProxies);
        assert!(if triangles { calls == 0.0 } else { calls > 0.0 }, "{case:?}");
        assert!(case.blas_bytes > 0 && case.geometry_bytes > 0, "{case:?}");
    }
    let points = &report.cases[0];
    // Prep merges duplicate points, so there are at most as many patches as the file's points.
    assert!(points.primitives > 35_000 && points.primitives <= 35_947, "{} patches", points.primitives);
    assert_eq!(points.paper_fps, None, "the paper has no 32x24 row");
    // The Bunny fits with unpacked hot records (64 bytes a patch); the ablation packs them (32).
    let packed = report.cases.iter().find(|c| c.variant == Variant::PackedRecords).expect("packed case");
    let unpacked_extra = 32 * points.primitives as u64;
    assert_eq!(points.geometry_bytes, packed.geometry_bytes + unpacked_extra, "{points:?} {packed:?}");
    assert_eq!(points.rays_per_frame, packed.rays_per_frame, "the same rays whatever the records' form");
    assert_eq!(report.limits.len(), 1, "one point-set case with a mesh twin");
    assert_eq!(renderer.validation_messages(), 0, "the validation layer reported messages");
}

#[test]
fn primary_rays_only_are_counted_exactly() {
    let Some(renderer) = renderer() else { return };
    let data = data_dir();
    let cache = tempfile::tempdir().expect("a temporary folder");
    // No lights (no shadow rays) and depth 1 (no reflections): one ray per sample.
    let text = r#"
        name = "primary only"
        [[models]]
        name = "Bunny"
        points = "points/bunny.ply"
        sizes = ["24x16"]
        [models.scene]
        render = { max_depth = 1, spp = 2 }
        camera = { position = [0.05, 0.19, 0.4], look_at = [-0.017, 0.1, 0.0], vfov_degrees = 40.0 }
        [[models.scene.objects]]
        name = "Bunny"
    "#;
    let suite = Suite::parse(text, Path::new("primary.toml")).expect("parses");
    let mut options = options(data, cache.path(), None, false);
    options.limit = false;
    let report = run_suite(&renderer, &suite, &options).expect("runs");
    assert_eq!(report.cases.len(), 1);
    assert_eq!(report.cases[0].rays_per_frame, 24 * 16 * 2);
}

#[test]
fn a_scene_file_times_the_path_integrator() {
    let Some(renderer) = renderer() else { return };
    let cache = tempfile::tempdir().expect("a temporary folder");
    let scene = cache.path().join("lit.toml");
    let bunny = data_dir().join("points/bunny.ply");
    let text = format!(
        "[render]\nwidth = 24\nheight = 16\nmax_depth = 5\n\
         [camera]\nposition = [0.05, 0.19, 0.4]\nlook_at = [-0.017, 0.1, 0.0]\n\
         [[lights]]\ntype = \"quad\"\ncorner = [-0.1, 0.4, -0.1]\nedge_u = [0.2, 0.0, 0.0]\nedge_v = [0.0, 0.0, 0.2]\n\
         [[objects]]\ntype = \"points\"\npath = {bunny:?}\n[[objects]]\ntype = \"ground\"\nauto = true\n"
    );
    std::fs::write(&scene, text).expect("the scene is written");
    let mut options = options(data_dir(), cache.path(), None, false);
    options.integrator = Some(Integrator::Path);
    let report = run_scene_file(&renderer, &scene, &options).expect("runs");
    let case = &report.cases[0];
    assert!(case.fps > 0.0, "{case:?}");
    // Every pixel's path: a primary ray, and where it meets a surface a shadow ray and a bounce.
    assert!(case.rays_per_frame > 2 * 24 * 16, "{case:?}");
    assert_eq!(renderer.validation_messages(), 0, "the validation layer reported messages");
}

/// A scene file of the bunny on a floor, in `folder`.
fn bunny_scene(folder: &Path) -> PathBuf {
    let scene = folder.join("bunny.toml");
    let bunny = data_dir().join("points/bunny.ply");
    let text = format!(
        "[render]\nwidth = 24\nheight = 16\n\
         [[objects]]\ntype = \"points\"\npath = {bunny:?}\n[[objects]]\ntype = \"ground\"\nauto = true\n"
    );
    std::fs::write(&scene, text).expect("the scene is written");
    scene
}

#[test]
fn a_scene_file_over_its_gpu_budget_is_timed_as_render_prepares_it() {
    let Some(renderer) = renderer() else { return };
    let cache = tempfile::tempdir().expect("a temporary folder");
    let scene = bunny_scene(cache.path());
    let options = options(data_dir(), cache.path(), None, false);
    let whole = run_scene_file(&renderer, &scene, &options).expect("runs").cases.remove(0);
    // Under what a box a patch takes, over what boxes of 4 take: render groups the patches.
    let budget = whole.blas_bytes + whole.geometry_bytes + whole.tlas_bytes - whole.blas_bytes / 2;
    let device = DeviceOptions { gpu_memory: Some(budget), ..DeviceOptions::VALIDATED };
    let tight = VulkanRenderer::new(DeviceSelector::Auto, device).expect("the renderer opens again");
    let grouped = run_scene_file(&tight, &scene, &options).expect("runs within the budget").cases.remove(0);
    assert!(grouped.blas_bytes < whole.blas_bytes / 2, "{grouped:?} against {whole:?}");
    assert_eq!(grouped.rays_per_frame, whole.rays_per_frame, "the same picture's rays");
    assert_eq!(tight.validation_messages(), 0, "the validation layer reported messages");
}

fn scale_options<'a>(data: PathBuf, cache: &Path, rungs: &[(&str, u64)]) -> ScaleOptions<'a> {
    ScaleOptions {
        data,
        cache: cache.to_path_buf(),
        scratch: None,
        rungs: rungs.iter().map(|&(label, points)| Rung { label: label.into(), points }).collect(),
        sizes: vec![(48, 27), (16, 16)],
        frames: FrameCounts { warmup: 1, timed: 2 },
        patches_per_box: None,
        hot_records: None,
        progress: &NoProgress,
        on_row: &|_| {},
    }
}

/// The one rung of `report`, which must have been measured.
fn measured(report: &ScaleReport) -> &RungMeasurement {
    match &report.rows[..] {
        [row] => match &row.outcome {
            RungOutcome::Measured(measurement) => measurement,
            RungOutcome::Skipped { reason } => panic!("{} was skipped: {reason}", row.label),
        },
        rows => panic!("{} rows", rows.len()),
    }
}

fn assert_sane(measurement: &RungMeasurement, points: u64) {
    let m = measurement;
    assert!(m.prep_seconds > 0.0 && m.prep_points_per_second > 0.0, "{m:?}");
    // The compact record's 28 bytes a patch, a block frame per 1024 patches and the header, and
    // the coarse level: about one 44-byte patch for every 16; a few points may merge as
    // duplicates.
    assert!(m.store_bytes > 29 * points && m.store_bytes < 32 * points, "{m:?}");
    assert!(m.prep_peak_rss_bytes.is_some_and(|bytes| bytes > 0), "{m:?}");
    assert!(m.load_seconds >= m.blas_build_seconds && m.blas_build_seconds > 0.0, "{m:?}");
    assert_eq!(m.bottom_levels, 2, "the points in one tile, and the floor: {m:?}");
    let sizes: Vec<(u32, u32)> = m.fps.iter().map(|s| (s.width, s.height)).collect();
    assert_eq!(sizes, [(48, 27), (16, 16)]);
    assert!(m.fps.iter().all(|s| s.fps > 0.0 && (s.fps * s.frame_ms - 1000.0).abs() < 1e-6), "{m:?}");
}

#[test]
fn scale_suite_runs_a_rung_on_the_cpu_backend() {
    let data = data_dir();
    let cache = tempfile::tempdir().expect("a temporary folder");
    let options = scale_options(data, cache.path(), &[("20K", 20_000)]);
    let report = run_scale(ScaleBackend(&Backend::Cpu), &options).expect("runs");
    let m = measured(&report);
    assert_sane(m, 20_000);
    assert_eq!(m.gpu_bytes_per_point, None, "no GPU on the CPU backend");
    assert_eq!(m.gpu_build_peak_bytes_per_point, None, "no GPU on the CPU backend");
    assert!(report.rows[0].stand_in.contains("20000 points sampled on meshes/dragon_res2.ply"));
    assert!(cache.path().join("dragon_res2-standin-20000-seed1.ply").is_file(), "the points are cached");
    let table = scale_markdown(&report);
    assert!(table.contains("| 20K |") && table.contains("FPS 48x27"), "{table}");
    serde_json::to_string(&report).expect("serialises");
}

/// Each rung's frame is held against the first rung's: the same rung again gives the same
/// image, another sample of the mesh a close one.
#[test]
fn scale_suite_compares_each_rungs_image_with_the_first() {
    let data = data_dir();
    let cache = tempfile::tempdir().expect("a temporary folder");
    let options = scale_options(data, cache.path(), &[("20K", 20_000), ("40K", 40_000), ("20K", 20_000)]);
    let report = run_scale(ScaleBackend(&Backend::Cpu), &options).expect("runs");
    let psnr: Vec<Option<f64>> = report
        .rows
        .iter()
        .map(|row| match &row.outcome {
            RungOutcome::Measured(m) => m.image_psnr_db,
            RungOutcome::Skipped { reason } => panic!("{} skipped: {reason}", row.label),
        })
        .collect();
    assert_eq!(psnr[0], None, "the first rung is the reference");
    let other_sample = psnr[1].expect("the second rung is compared");
    assert!(
        other_sample.is_finite() && other_sample > 15.0,
        "20K and 40K points of one mesh: {other_sample} dB"
    );
    assert_eq!(psnr[2], Some(f64::INFINITY), "the first rung again");
}

#[test]
fn scale_suite_reports_gpu_bytes_on_vulkan() {
    let Some(renderer) = renderer() else { return };
    let data = data_dir();
    let cache = tempfile::tempdir().expect("a temporary folder");
    let options = scale_options(data, cache.path(), &[("20K", 20_000)]);
    let counter = renderer.message_counter();
    let backend = Backend::Vulkan(Box::new(renderer));
    let report = run_scale(ScaleBackend(&backend), &options).expect("runs");
    let m = measured(&report);
    assert_sane(m, 20_000);
    // The hot records (32 bytes a patch) and the BLAS; no boxes, no combined records, and
    // no cold ones: the dragon's material does not colour by the points.
    let bytes = m.gpu_bytes_per_point.expect("GPU bytes on Vulkan");
    eprintln!("{bytes:.1} GPU bytes a point");
    assert!(bytes > 32.0 && bytes < 180.0, "{bytes} B/point");
    // Building held the scene and, for a while, the boxes and scratch besides.
    let peak = m.gpu_build_peak_bytes_per_point.expect("the build's peak on Vulkan");
    assert!(peak >= bytes && peak < 3.0 * bytes, "{peak} B/point at the peak, {bytes} kept");
    drop(backend);
    assert_eq!(counter.count(), 0, "the validation layer reported messages");
}

#[test]
fn scale_suite_skips_what_does_not_fit_and_stays_out_of_checkouts() {
    let data = data_dir();
    let cache = tempfile::tempdir().expect("a temporary folder");
    let options = scale_options(data.clone(), cache.path(), &[("1P", 1_000_000_000_000_000)]);
    let report = run_scale(ScaleBackend(&Backend::Cpu), &options).expect("runs");
    match &report.rows[0].outcome {
        RungOutcome::Skipped { reason } => assert!(reason.contains("GB of memory"), "{reason}"),
        RungOutcome::Measured(_) => panic!("a petapoint cloud cannot fit"),
    }
    assert!(scale_markdown(&report).contains("| 1P | skipped: rendering on the CPU needs"));
    std::fs::create_dir(cache.path().join(".git")).expect("a fake checkout");
    let inside = cache.path().join("cache");
    let error =
        run_scale(ScaleBackend(&Backend::Cpu), &scale_options(data, &inside, &[])).expect_err("refused");
    assert!(matches!(error, BenchError::CacheInRepository { .. }), "{error}");
    assert!(!inside.exists(), "nothing was written");
}
