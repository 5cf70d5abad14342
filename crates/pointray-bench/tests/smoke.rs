//! CI smoke test (lavapipe is enough): the table1 suite runs end to end on one small model and
//! its numbers are sane; the GPU ray count is exact where it can be computed by hand. It
//! asserts that the benchmark works, not how fast anything is.

use std::path::{Path, PathBuf};

use pointray_bench::{BenchOptions, FrameCounts, Suite, Variant, run_suite};
use pointray_vulkan::{DeviceSelector, VulkanRenderer};

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

fn renderer() -> Option<VulkanRenderer> {
    match VulkanRenderer::with_validation(DeviceSelector::Auto, true) {
        Ok(renderer) => Some(renderer),
        Err(error) if error.is_no_device() => {
            assert!(!in_ci(), "CI=true but no usable Vulkan device: {error}");
            eprintln!("note: skipping, no usable Vulkan device: {error}");
            None
        }
        Err(error) => panic!("creating the renderer failed: {error}"),
    }
}

/// `../shared/data` beside the workspace, or `POINTRAY_DATA`; `None` outside CI when missing.
fn data_dir() -> Option<PathBuf> {
    let root = std::env::var_os("POINTRAY_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    if root.join("points/bunny.ply").is_file() {
        return Some(root);
    }
    assert!(!in_ci(), "CI=true but the test data {} is missing", root.display());
    eprintln!("note: skipping, test data {} is missing", root.display());
    None
}

fn options<'a>(data: PathBuf, cache: &Path, size: Option<(u32, u32)>, ablations: bool) -> BenchOptions<'a> {
    BenchOptions {
        data,
        cache: cache.to_path_buf(),
        frames: FrameCounts { warmup: 1, timed: 3 },
        size,
        limit: true,
        ablations,
        reordering: None,
        models: vec!["Bunny".into()],
        on_case: &|_| {},
    }
}

#[test]
fn table1_bunny_runs_with_limit_and_ablations() {
    let (Some(renderer), Some(data)) = (renderer(), data_dir()) else { return };
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
            Variant::SmallerDisks,
            Variant::PaperRadius,
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
        assert!(case.blas_bytes > 0 && case.geometry_bytes > 0, "{case:?}");
    }
    let points = &report.cases[0];
    // Prep merges duplicate points, so there are at most as many patches as the file's points.
    assert!(points.primitives > 35_000 && points.primitives <= 35_947, "{} patches", points.primitives);
    assert_eq!(points.paper_fps, None, "the paper has no 32x24 row");
    assert_eq!(report.limits.len(), 1, "one point-set case with a mesh twin");
    assert_eq!(renderer.validation_messages(), 0, "the validation layer reported messages");
}

#[test]
fn primary_rays_only_are_counted_exactly() {
    let (Some(renderer), Some(data)) = (renderer(), data_dir()) else { return };
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
