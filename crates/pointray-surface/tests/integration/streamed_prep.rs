//! Prep from a cloud read in chunks and sorted out of core writes the patches that the
//! in-memory tiled prep writes, and the same store, byte for byte, whether one process preps
//! every tile or each tile is prepped alone and the tile files merged, with the coarse level
//! made from the stored patches; budgets too small are refused.

use std::path::{Path, PathBuf};

use pointray_io::formats::ply::write_point_cloud;
use pointray_io::formats::read_point_cloud;
use pointray_io::{MemoryBudget, PointStream};
use pointray_kernels::COLOR_NEIGHBORS;
use pointray_patches::PrepSettings;
use pointray_patches::coarse_level::CoarseLevel;
use pointray_patches::patch_store;
use pointray_surface::NoProgress;
use pointray_surface::tiles::kept_sort::{is_kept_sort, keep_sort};
use pointray_surface::tiles::merge::{MergedTiles, merge_tile_files};
use pointray_surface::tiles::stream_error::StreamError;
use pointray_surface::tiles::streamed_prep::{
    prep_kept_streamed, prep_one_kept_tile, prep_one_tile, prep_streamed,
};
use pointray_surface::tiles::streamed_tiles::TileCount;
use pointray_surface::tiles::tiled_prep::prep_tiled;

use crate::tiled_prep::coloured_sheet;

const PLENTY: MemoryBudget = MemoryBudget { bytes: 4 << 30 };
const KEEP_TILES: (MemoryBudget, MergedTiles) = (PLENTY, MergedTiles::Kept);

/// The sheet as a PLY file, and its settings.
fn sheet_file(dir: &Path) -> (PathBuf, PrepSettings) {
    let (cloud, settings) = coloured_sheet();
    cloud_file(dir, cloud, settings)
}

/// The sheet (without its colours unless `coloured`) with every 50th point given twice, so
/// that prep merges points and the store holds fewer patches than the input's points.
fn sheet_with_duplicates_file(dir: &Path, coloured: bool) -> (PathBuf, PrepSettings) {
    let (mut cloud, settings) = coloured_sheet();
    let colors = cloud.colors.as_mut().expect("a coloured sheet");
    for i in (0..cloud.positions.len()).step_by(50) {
        cloud.positions.push(cloud.positions[i]);
        colors.push(colors[i]);
    }
    if !coloured {
        cloud.colors = None;
    }
    cloud_file(dir, cloud, settings)
}

fn cloud_file(dir: &Path, cloud: pointray_io::PointCloud, settings: PrepSettings) -> (PathBuf, PrepSettings) {
    let path = dir.join("sheet.ply");
    write_point_cloud(&path, &cloud).unwrap();
    (path, settings)
}

fn open(path: &Path) -> PointStream {
    PointStream::open(path, None, PLENTY).unwrap()
}

/// The store `output` with its scratch folder made beside it.
fn places(output: &Path) -> (&Path, &Path) {
    (output, output.parent().expect("a file in a folder"))
}

/// Only the store and the input are left: scratch folders are gone.
fn assert_no_scratch(dir: &Path, expected: usize) {
    let names: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), expected, "scratch left behind: {names:?}");
}

#[test]
fn streamed_tiles_write_the_in_memory_tiled_store() {
    let dir = tempfile::tempdir().unwrap();
    let (path, settings) = sheet_file(dir.path());
    let cloud = read_point_cloud(&path).unwrap();
    let in_memory = dir.path().join("in_memory.patches");
    patch_store::write(&in_memory, &prep_tiled(&cloud, &settings, 8, &NoProgress).unwrap()).unwrap();
    let streamed = dir.path().join("streamed.patches");
    // The points sorted in a folder of their own, as on another disk.
    let scratch = tempfile::tempdir().unwrap();
    let cut = (TileCount::Exactly(8), PLENTY);
    let summary =
        prep_streamed(&mut open(&path), &settings, cut, (&streamed, scratch.path()), &NoProgress).unwrap();
    assert_eq!((summary.tiles, summary.input_points), (8, cloud.len() as u64));
    assert!(std::fs::read(&streamed).unwrap() == std::fs::read(&in_memory).unwrap(), "same bytes");
    assert_no_scratch(dir.path(), 3);
    assert_no_scratch(scratch.path(), 0);
}

#[test]
fn streamed_tiles_that_merge_points_write_the_in_memory_tiled_patches() {
    for coloured in [true, false] {
        let dir = tempfile::tempdir().unwrap();
        let (path, settings) = sheet_with_duplicates_file(dir.path(), coloured);
        let cloud = read_point_cloud(&path).unwrap();
        let in_memory = prep_tiled(&cloud, &settings, 8, &NoProgress).unwrap();
        assert!(in_memory.len() < cloud.len(), "duplicates merged: {} patches", in_memory.len());
        assert_eq!(in_memory.color_neighbors.is_empty(), !coloured);
        let streamed = dir.path().join("streamed.patches");
        let cut = (TileCount::Exactly(8), PLENTY);
        prep_streamed(&mut open(&path), &settings, cut, places(&streamed), &NoProgress).unwrap();
        let in_memory_store = dir.path().join("in_memory.patches");
        patch_store::write(&in_memory_store, &in_memory).unwrap();
        let streamed = patch_store::read(&streamed).unwrap();
        assert_eq!(streamed, patch_store::read(&in_memory_store).unwrap());
        let made = CoarseLevel::of(&streamed);
        assert_eq!(streamed.coarse.as_deref(), Some(&made), "the coarse level written as the tiles came");
        assert_no_scratch(dir.path(), 3);
    }
}

#[test]
fn tiles_prepped_alone_merge_into_the_single_process_store() {
    let dir = tempfile::tempdir().unwrap();
    let (path, settings) = sheet_with_duplicates_file(dir.path(), true);
    let whole = dir.path().join("whole.patches");
    prep_streamed(&mut open(&path), &settings, (TileCount::AtLeast(4), PLENTY), places(&whole), &NoProgress)
        .unwrap();
    let tiles: Vec<PathBuf> = (0..4).rev().map(|i| dir.path().join(format!("tile{i}.tile"))).collect();
    for (i, tile) in tiles.iter().rev().enumerate() {
        prep_one_tile(&mut open(&path), &settings, (i, 4), PLENTY, places(tile), &NoProgress).unwrap();
    }
    let merged = dir.path().join("merged.patches");
    merge_tile_files(&tiles, &merged, KEEP_TILES, &NoProgress).unwrap();
    assert!(std::fs::read(&merged).unwrap() == std::fs::read(&whole).unwrap(), "same bytes");

    let error =
        merge_tile_files(&tiles[1..], &dir.path().join("m.patches"), KEEP_TILES, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("tile 3 of 4 is missing"), "{error}");
    let twice = [tiles.clone(), vec![tiles[0].clone()]].concat();
    let error = merge_tile_files(&twice, &dir.path().join("m.patches"), KEEP_TILES, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("is also"), "{error}");
    let error =
        merge_tile_files(std::slice::from_ref(&path), &dir.path().join("m.patches"), KEEP_TILES, &NoProgress)
            .unwrap_err();
    assert!(error.to_string().contains("sheet.ply: not a pointray tile file"), "{error}");
    // Two tiles as read and decoded (four times the largest file) beside the map and the coarse
    // level, past what the program itself takes (32 MiB).
    let largest = tiles.iter().map(|tile| std::fs::metadata(tile).unwrap().len()).max().unwrap();
    let short = MemoryBudget { bytes: (32 << 20) + 4 * largest };
    let error =
        merge_tile_files(&tiles, &dir.path().join("m.patches"), (short, MergedTiles::Kept), &NoProgress)
            .unwrap_err();
    assert!(matches!(error, StreamError::OverBudget { .. }), "{error}");
    assert!(error.to_string().contains("beside two tiles as read and decoded"), "{error}");
    let enough = MemoryBudget { bytes: (33 << 20) + 4 * largest };
    merge_tile_files(&tiles, &dir.path().join("m.patches"), (enough, MergedTiles::Kept), &NoProgress)
        .unwrap();
}

#[test]
fn tile_jobs_on_a_kept_sort_merge_into_the_single_process_store() {
    let dir = tempfile::tempdir().unwrap();
    let (path, settings) = sheet_with_duplicates_file(dir.path(), true);
    let whole = dir.path().join("whole.patches");
    prep_streamed(&mut open(&path), &settings, (TileCount::AtLeast(4), PLENTY), places(&whole), &NoProgress)
        .unwrap();
    let kept = dir.path().join("sheet.sorted");
    let points = keep_sort(&mut open(&path), &settings, PLENTY, &kept, &NoProgress).unwrap();
    assert_eq!(points, read_point_cloud(&path).unwrap().len() as u64);
    assert!(is_kept_sort(&kept) && !is_kept_sort(&path));
    let tiles: Vec<PathBuf> = (0..4).map(|i| dir.path().join(format!("tile{i}.tile"))).collect();
    for (i, tile) in tiles.iter().enumerate() {
        prep_one_kept_tile(&kept, &settings, (i, 4), PLENTY, tile, &NoProgress).unwrap();
    }
    // Each patch's hot and cold records (44 bytes), input point and colour neighbours, and no box.
    let per_patch = 44 + 4 + 4 * COLOR_NEIGHBORS as u64;
    let patches = patch_store::read(&whole).unwrap().len() as u64;
    let bytes: u64 = tiles.iter().map(|tile| std::fs::metadata(tile).unwrap().len()).sum();
    let records = per_patch * patches;
    assert!((records..records + 4096).contains(&bytes), "{bytes} bytes of tiles for {patches} patches");
    let merged = dir.path().join("merged.patches");
    let removing = (PLENTY, MergedTiles::Removed);
    let error = merge_tile_files(&tiles[..3], &merged, removing, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("tile 3 of 4 is missing"), "{error}");
    assert!(tiles.iter().all(|tile| tile.exists()), "a refused merge removes no tile");
    let damaged = dir.path().join("damaged.tile");
    let mut bytes = std::fs::read(&tiles[3]).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 1;
    std::fs::write(&damaged, bytes).unwrap();
    let cut = [&tiles[..3], std::slice::from_ref(&damaged)].concat();
    let error = merge_tile_files(&cut, &merged, removing, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("damaged.tile: corrupted"), "{error}");
    assert!(cut.iter().all(|tile| tile.exists()), "every tile is checked before the first goes");
    // Kept tiles are read as they are merged: the damaged one stops the merge there.
    let error = merge_tile_files(&cut, &merged, KEEP_TILES, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("damaged.tile: corrupted"), "{error}");
    assert!(!merged.exists(), "a failed merge writes no store");
    std::fs::remove_file(&damaged).unwrap();
    merge_tile_files(&tiles, &merged, removing, &NoProgress).unwrap();
    assert!(std::fs::read(&merged).unwrap() == std::fs::read(&whole).unwrap(), "same bytes");
    assert!(tiles.iter().all(|tile| !tile.exists()), "each tile removed once merged");
    // The whole cloud prepped from the kept sort, in one process.
    let from_kept = dir.path().join("from_kept.patches");
    prep_kept_streamed(&kept, &settings, (TileCount::AtLeast(4), PLENTY), &from_kept, &NoProgress).unwrap();
    assert!(std::fs::read(&from_kept).unwrap() == std::fs::read(&whole).unwrap(), "same bytes");
    // The input, the stores and the kept sort: no scratch is left.
    assert_no_scratch(dir.path(), 5);

    let error = keep_sort(&mut open(&path), &settings, PLENTY, &kept, &NoProgress).unwrap_err();
    assert!(error.to_string().contains("already exists"), "{error}");
    let records = kept.join("points");
    let length = std::fs::metadata(&records).unwrap().len();
    std::fs::OpenOptions::new().write(true).open(&records).unwrap().set_len(length - 1).unwrap();
    let error = prep_one_kept_tile(&kept, &settings, (0, 4), PLENTY, &dir.path().join("t.tile"), &NoProgress)
        .unwrap_err();
    assert!(error.to_string().contains("not the"), "{error}");
    std::fs::write(kept.join("index"), b"PRSORT01").unwrap();
    let error = prep_one_kept_tile(&kept, &settings, (0, 4), PLENTY, &dir.path().join("t.tile"), &NoProgress)
        .unwrap_err();
    assert!(error.to_string().contains("sheet.sorted: not a sort"), "{error}");
}

#[test]
fn budgets_too_small_are_refused_with_what_would_fit() {
    let dir = tempfile::tempdir().unwrap();
    let (path, settings) = sheet_file(dir.path());
    let output = dir.path().join("out.patches");
    let tiny = MemoryBudget { bytes: (32 << 20) + (512 << 10) };
    let error = prep_streamed(
        &mut open(&path),
        &settings,
        (TileCount::AtLeast(1), tiny),
        places(&output),
        &NoProgress,
    )
    .unwrap_err();
    assert!(matches!(error, StreamError::OverBudget { .. }), "{error}");
    assert!(error.to_string().contains("cannot hold one tile"), "{error}");
    let advised: u64 = error
        .to_string()
        .split("give it at least ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("the refusal advises a budget: {error}"));
    // A lower bound: tiles that small may still find halos beyond it, but the budget holds the
    // patch map and one tile.
    let advised = MemoryBudget { bytes: advised << 20 };
    let result = prep_streamed(
        &mut open(&path),
        &settings,
        (TileCount::AtLeast(1), advised),
        places(&output),
        &NoProgress,
    );
    assert!(
        result.as_ref().err().is_none_or(|error| !error.to_string().contains("cannot hold")),
        "{:?}",
        result.err()
    );
    let _ = std::fs::remove_file(&output);
    let small = MemoryBudget { bytes: 38 << 20 };
    let error =
        prep_one_tile(&mut open(&path), &settings, (0, 1), small, places(&output), &NoProgress).unwrap_err();
    assert!(error.to_string().contains("cut the cloud into at least"), "{error}");
    assert!(!output.exists());
    assert_no_scratch(dir.path(), 1);
}

#[test]
fn a_streamed_prep_called_from_a_thread_pool_writes_the_same_store() {
    let dir = tempfile::tempdir().unwrap();
    let (path, settings) = sheet_file(dir.path());
    let (alone, within) = (dir.path().join("alone.patches"), dir.path().join("within.patches"));
    let prep = |output: &Path| {
        prep_streamed(
            &mut open(&path),
            &settings,
            (TileCount::Exactly(4), PLENTY),
            places(output),
            &NoProgress,
        )
    };
    prep(&alone).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    pool.install(|| prep(&within)).unwrap();
    assert!(std::fs::read(&alone).unwrap() == std::fs::read(&within).unwrap(), "same bytes");
}
