//! The prep cache: a second load reuses the cache file without running prep, a corrupt cache
//! is regenerated, changed settings get their own file, and the input's folder is never
//! written.

use crate::common;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use glam::DVec3;
use pointray_scene::{Geometry, LoadOptions, LoadedScene, PointSetOrigin, SceneError, load_scene};
use pointray_surface::{PrepProgress, Stage};

/// Counts how many times prep started.
#[derive(Default)]
struct PrepRuns(AtomicUsize);

impl PrepProgress for PrepRuns {
    fn stage_started(&self, stage: Stage, _items: u64) {
        if stage == Stage::Validate {
            self.0.fetch_add(1, Ordering::SeqCst);
        }
    }
    fn advanced(&self, _items: u64) {}
    fn stage_finished(&self, _stage: Stage, _elapsed: Duration) {}
}

impl PrepRuns {
    fn count(&self) -> usize {
        self.0.load(Ordering::SeqCst)
    }
}

struct Fixture {
    input_dir: tempfile::TempDir,
    cache_dir: tempfile::TempDir,
    scene: PathBuf,
}

fn fixture(object_extra: &str) -> Fixture {
    let input_dir = tempfile::tempdir().unwrap();
    common::write_sphere_ply(&input_dir.path().join("ball.ply"), DVec3::new(1.0, 2.0, 3.0), 1500);
    let scene = input_dir.path().join("scene.toml");
    std::fs::write(&scene, format!("[[objects]]\ntype = \"points\"\npath = \"ball.ply\"\n{object_extra}"))
        .unwrap();
    Fixture { input_dir, cache_dir: tempfile::tempdir().unwrap(), scene }
}

fn load(fixture: &Fixture, runs: &PrepRuns) -> LoadedScene {
    let options =
        LoadOptions { cache_dir: Some(fixture.cache_dir.path()), progress: runs, ..LoadOptions::default() };
    load_scene(&fixture.scene, &options).unwrap()
}

fn cache_file(loaded: &LoadedScene) -> PathBuf {
    match &loaded.point_sets[0].1 {
        PointSetOrigin::Prepped { cache: Some(cache) }
        | PointSetOrigin::CacheHit { cache }
        | PointSetOrigin::CacheRegenerated { cache, .. } => cache.clone(),
        other => panic!("no cache file: {other:?}"),
    }
}

fn patch_count(loaded: &LoadedScene) -> usize {
    match &loaded.scene.objects[0].geometry {
        Geometry::Patches(patches) => patches.len(),
        Geometry::Mesh(_) => panic!("a point set"),
    }
}

#[test]
fn a_second_load_reuses_the_cache_without_running_prep() {
    let fixture = fixture("");
    let runs = PrepRuns::default();
    let first = load(&fixture, &runs);
    assert_eq!(runs.count(), 1);
    let cache = cache_file(&first);
    assert!(matches!(first.point_sets[0].1, PointSetOrigin::Prepped { .. }));
    assert_eq!(cache.parent().unwrap(), fixture.cache_dir.path());
    let name = cache.file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with("ball-") && name.ends_with(".patches"), "{name}");
    let written = std::fs::metadata(&cache).unwrap().modified().unwrap();

    let second = load(&fixture, &runs);
    assert_eq!(runs.count(), 1, "prep ran again");
    assert_eq!(second.point_sets[0].1, PointSetOrigin::CacheHit { cache: cache.clone() });
    assert_eq!(std::fs::metadata(&cache).unwrap().modified().unwrap(), written, "the cache was rewritten");
    let (Geometry::Patches(a), Geometry::Patches(b)) =
        (&first.scene.objects[0].geometry, &second.scene.objects[0].geometry)
    else {
        panic!("point sets")
    };
    assert_eq!(a, b, "the cached patches are the prepped ones");
    assert_eq!(first.scene.objects[0].transform, second.scene.objects[0].transform);
}

#[test]
fn a_corrupt_cache_is_regenerated() {
    let fixture = fixture("");
    let runs = PrepRuns::default();
    let cache = cache_file(&load(&fixture, &runs));
    let mut bytes = std::fs::read(&cache).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x5a;
    std::fs::write(&cache, &bytes).unwrap();

    let reloaded = load(&fixture, &runs);
    assert_eq!(runs.count(), 2, "prep ran again");
    match &reloaded.point_sets[0].1 {
        PointSetOrigin::CacheRegenerated { cache: regenerated, problem } => {
            assert_eq!(regenerated, &cache);
            assert!(problem.contains("checksum"), "{problem}");
        }
        other => panic!("expected a regenerated cache, got {other:?}"),
    }
    pointray_patches::patch_store::read(&cache).expect("the regenerated cache is valid");
    assert_eq!(patch_count(&reloaded), 1500);

    std::fs::write(&cache, &bytes[..100]).unwrap();
    let truncated = load(&fixture, &runs);
    assert!(matches!(truncated.point_sets[0].1, PointSetOrigin::CacheRegenerated { .. }));
    assert_eq!(runs.count(), 3);
}

#[test]
fn different_settings_and_a_changed_input_get_their_own_cache_files() {
    let plain = fixture("");
    let runs = PrepRuns::default();
    let default_cache = cache_file(&load(&plain, &runs));
    std::fs::write(&plain.scene, "[[objects]]\ntype = \"points\"\npath = \"ball.ply\"\nprep = { k = 12 }\n")
        .unwrap();
    let k12_cache = cache_file(&load(&plain, &runs));
    assert_ne!(default_cache, k12_cache);
    assert_eq!(runs.count(), 2);

    // A rewritten input (new size and time) must not reuse the old result.
    std::thread::sleep(Duration::from_millis(20));
    common::write_sphere_ply(&plain.input_dir.path().join("ball.ply"), DVec3::ZERO, 1700);
    let changed = load(&plain, &runs);
    assert_eq!(runs.count(), 3);
    assert_ne!(cache_file(&changed), k12_cache);
    assert_eq!(patch_count(&changed), 1700);
}

#[test]
fn the_input_folder_is_never_written() {
    let fixture = fixture("");
    let before = common::listing(fixture.input_dir.path());
    set_read_only(fixture.input_dir.path(), true);
    let runs = PrepRuns::default();
    load(&fixture, &runs);
    load(&fixture, &runs);
    // Without a cache folder, nothing is written anywhere.
    load_scene(&fixture.scene, &LoadOptions::default()).unwrap();
    set_read_only(fixture.input_dir.path(), false);
    assert_eq!(common::listing(fixture.input_dir.path()), before);
    let entries = common::listing(fixture.cache_dir.path());
    let stores = entries.iter().filter(|name| name.ends_with(".patches")).count();
    assert_eq!(stores, 1, "one cache file, beside the cache's tag and list: {entries:?}");
}

#[test]
fn a_patch_store_input_loads_directly() {
    let fixture = fixture("");
    let cache = cache_file(&load(&fixture, &PrepRuns::default()));
    let store = fixture.input_dir.path().join("ball.patches");
    std::fs::copy(&cache, &store).unwrap();
    std::fs::write(&fixture.scene, "[[objects]]\ntype = \"points\"\npath = \"ball.patches\"\n").unwrap();
    let runs = PrepRuns::default();
    let loaded = load(&fixture, &runs);
    assert_eq!(runs.count(), 0);
    assert_eq!(loaded.point_sets[0].1, PointSetOrigin::PatchStore);
    let bounds = loaded.scene.objects[0].world_bounds().unwrap();
    let center = pointray_scene::bounds::center(&bounds);
    assert!((center - glam::Vec3::new(1.0, 2.0, 3.0)).length() < 1e-3, "{center}");

    std::fs::write(
        &fixture.scene,
        "[[objects]]\ntype = \"points\"\npath = \"ball.patches\"\nprep = { k = 12 }\n",
    )
    .unwrap();
    let options = LoadOptions { cache_dir: Some(fixture.cache_dir.path()), ..LoadOptions::default() };
    let error = load_scene(&fixture.scene, &options).unwrap_err();
    assert!(matches!(error, SceneError::Invalid { .. }), "{error:?}");
    assert!(error.to_string().contains("ball.patches"), "{error}");
}

#[test]
fn an_unusable_cache_folder_is_a_clear_error() {
    let fixture = fixture("");
    let blocker = fixture.cache_dir.path().join("not-a-folder");
    std::fs::write(&blocker, b"").unwrap();
    let options = LoadOptions { cache_dir: Some(&blocker), ..LoadOptions::default() };
    let error = load_scene(&fixture.scene, &options).unwrap_err();
    assert!(matches!(error, SceneError::CacheDir { .. }), "{error:?}");
    assert!(error.to_string().contains("not-a-folder"), "{error}");
}

/// Read-only for everyone (`r-x`), or back to `rwx` for the owner. Under root the
/// permission bits do not stop writes, which is why the test compares listings too.
fn set_read_only(dir: &Path, read_only: bool) {
    use std::os::unix::fs::PermissionsExt;
    let mode = if read_only { 0o555 } else { 0o755 };
    std::fs::set_permissions(dir, std::fs::Permissions::from_mode(mode)).unwrap();
}

/// `cp -p`, `rsync -t` and `touch -r` give a different cloud the size and time of the one
/// cached: the key follows the contents, so it gets its own entry, not the old cloud.
#[test]
fn a_different_cloud_of_the_same_size_and_time_gets_its_own_cache_file() {
    let fixture = fixture("");
    let runs = PrepRuns::default();
    let input = fixture.input_dir.path().join("ball.ply");
    let first = cache_file(&load(&fixture, &runs));
    let (size, time) = std::fs::metadata(&input).map(|m| (m.len(), m.modified().unwrap())).unwrap();
    common::write_sphere_ply(&input, DVec3::new(-4.0, 5.0, 0.0), 1500);
    std::fs::File::options().write(true).open(&input).unwrap().set_modified(time).unwrap();
    let metadata = std::fs::metadata(&input).unwrap();
    assert_eq!((metadata.len(), metadata.modified().unwrap()), (size, time), "the same size and time");

    let second = load(&fixture, &runs);
    assert_eq!(runs.count(), 2, "prep ran for the new cloud");
    assert_ne!(cache_file(&second), first);
    let center = pointray_scene::bounds::center(&second.scene.objects[0].world_bounds().unwrap());
    assert!((center - glam::Vec3::new(-4.0, 5.0, 0.0)).length() < 1e-3, "the new cloud: {center}");
}

#[test]
fn objects_naming_one_points_file_alike_share_its_patches() {
    let copies = "[objects.transform]\ntranslate = [0.0, 0.0, 0.0]\n\
                  [[objects]]\ntype = \"points\"\npath = \"ball.ply\"\n\
                  [objects.transform]\ntranslate = [3.0, 0.0, 0.0]\n\
                  [[objects]]\ntype = \"points\"\npath = \"ball.ply\"\n[objects.prep]\nk = 12\n";
    let fixture = fixture(copies);
    let runs = PrepRuns::default();
    let loaded = load(&fixture, &runs);
    assert_eq!(runs.count(), 2, "prepped once for the default settings and once for k = 12");
    let patches: Vec<_> = loaded
        .scene
        .objects
        .iter()
        .map(|object| match &object.geometry {
            Geometry::Patches(patches) => patches.clone(),
            Geometry::Mesh(_) => panic!("a point set"),
        })
        .collect();
    assert!(std::sync::Arc::ptr_eq(&patches[0], &patches[1]), "the two copies share one set");
    assert!(!std::sync::Arc::ptr_eq(&patches[0], &patches[2]), "another prep is another set");
    assert_ne!(loaded.scene.objects[0].transform, loaded.scene.objects[1].transform);
}
