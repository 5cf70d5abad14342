//! Tile files merged into one patch store, tile by tile through the writer a single process
//! uses (`StoreInPlace`), so that no more than one tile's patches and a map from input points
//! to patches are in memory at once: the store a single process prepping the same tiles
//! writes, byte for byte. Where a disk cannot hold the tile files and the store at once, the
//! merge can remove each tile file as soon as its records are in the store.

use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_io::MemoryBudget;
use pointray_io::disk_space::file_system;
use pointray_patches::PrepSettings;

use crate::prep_progress::{PrepProgress, Stage};
use crate::tiles::disk_room::{Need, ensure_room, store_need};
use crate::tiles::spool::TileSpool;
use crate::tiles::stream_budget::{STORE_BYTES_PER_POINT, StreamBudget};
use crate::tiles::stream_error::StreamError;
use crate::tiles::tile_file::{TileRecords, read_tile_file, read_tile_header};

/// What a merge wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MergeSummary {
    pub tiles: usize,
    pub input_points: u64,
    pub patches: u64,
}

/// What becomes of the tile files a merge reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MergedTiles {
    Kept,
    /// Each is removed once its records are written, after every tile has been read and
    /// checked whole: what frees the disk for the store where it cannot hold both. A merge
    /// that fails after that leaves the removed tiles to be prepped again.
    Removed,
}

/// Merges the tile files `tiles` (every tile of one cut, in any order) into the store
/// `output`, written atomically.
pub fn merge_tile_files(
    tiles: &[PathBuf],
    output: &Path,
    (memory, merged): (MemoryBudget, MergedTiles),
    progress: &dyn PrepProgress,
) -> Result<MergeSummary, StreamError> {
    merge_ordered_tile_files(&in_tile_order(tiles)?, output, (memory, merged), progress)
}

/// Merges tile files already in order (at least one) into the store `output`. One tile is
/// read while the one before it is written; a merge that removes its tiles first reads and
/// checks them all, so that no tile goes before every one is known to be whole.
pub(crate) fn merge_ordered_tile_files(
    ordered: &[PathBuf],
    output: &Path,
    (memory, merged): (MemoryBudget, MergedTiles),
    progress: &dyn PrepProgress,
) -> Result<MergeSummary, StreamError> {
    let first = read_tile_header(&ordered[0])?;
    ensure_memory(ordered, first.input_points, memory, output)?;
    ensure_room(&[store_room_need(output, first.input_points, ordered, merged)])?;
    progress.stage_started(Stage::MergeTiles, first.input_points);
    let started = std::time::Instant::now();
    if merged == MergedTiles::Removed {
        check_tiles(ordered)?;
    }
    let mut spool: Option<TileSpool> = None;
    std::thread::scope(|scope| -> Result<(), StreamError> {
        let (send, receive) = std::sync::mpsc::sync_channel(0);
        scope.spawn(move || {
            for path in ordered {
                let tile = read_tile_file(path);
                let failed = tile.is_err();
                if send.send((path, tile)).is_err() || failed {
                    break;
                }
            }
        });
        for (path, tile) in receive {
            let (_, tile) = tile?;
            let spool = match &mut spool {
                Some(spool) => spool,
                None => spool.insert(TileSpool::new(output, first.input_points, frame_of(&tile))?),
            };
            same_frame(spool.frame(), &tile, path, &ordered[0])?;
            let records = &tile.records;
            spool.push_records((&records.hot, &records.cold, &tile.color_neighbors), &tile.sources)?;
            if merged == MergedTiles::Removed {
                std::fs::remove_file(path).map_err(|e| StreamError::scratch(path, e))?;
            }
            progress.advanced(tile.sources.len() as u64);
        }
        Ok(())
    })?;
    let written = spool.expect("at least one tile, or an error").finish()?;
    progress.stage_finished(Stage::MergeTiles, started.elapsed());
    Ok(written)
}

/// Refuses a budget that cannot hold the map from points to patches and the coarse level
/// beside two tiles, each as read and as decoded (about twice its file).
fn ensure_memory(
    ordered: &[PathBuf],
    input_points: u64,
    memory: MemoryBudget,
    output: &Path,
) -> Result<(), StreamError> {
    let largest = ordered.iter().filter_map(|path| std::fs::metadata(path).ok()).map(|meta| meta.len()).max();
    let tiles = 4 * largest.unwrap_or(0);
    let budget = StreamBudget::new(memory, 0);
    if budget.holds_store_writing(input_points) && budget.with_store_writing(input_points).usable() >= tiles {
        return Ok(());
    }
    let problem = format!(
        "merging tiles of {input_points} points maps each to its patch and holds the coarse level \
         ({STORE_BYTES_PER_POINT} bytes a point) beside two tiles as read and decoded ({} MiB), which \
         the memory budget cannot hold",
        tiles >> 20
    );
    Err(StreamError::OverBudget { path: output.to_path_buf(), problem })
}

/// Reads every tile whole, and checks that they were prepped alike.
fn check_tiles(ordered: &[PathBuf]) -> Result<(), StreamError> {
    let mut frame = None;
    for path in ordered {
        let (_, tile) = read_tile_file(path)?;
        same_frame(*frame.get_or_insert(frame_of(&tile)), &tile, path, &ordered[0])?;
    }
    Ok(())
}

/// The settings and offset a tile was prepped with.
fn frame_of(tile: &TileRecords) -> (PrepSettings, DVec3) {
    (tile.records.settings, tile.records.offset)
}

/// Refuses the tile at `path` unless it was prepped with the settings and offset of the
/// first tile, at `first`.
fn same_frame(
    expected: (PrepSettings, DVec3),
    tile: &TileRecords,
    path: &Path,
    first: &Path,
) -> Result<(), StreamError> {
    if frame_of(tile) == expected {
        return Ok(());
    }
    let problem = format!(
        "its prep settings or offset differ from {}'s: the tiles come from different preps",
        first.display()
    );
    Err(StreamError::BadTile { path: path.to_path_buf(), problem })
}

/// The room the store of `input_points` points needs beside what is on the output's disk:
/// less, when the tiles merged into it are removed, by all but the largest of those that lie
/// on its file system, since a tile is removed only once its records are written.
fn store_room_need<'a>(
    output: &'a Path,
    input_points: u64,
    tiles: &[PathBuf],
    merged: MergedTiles,
) -> Need<'a> {
    let folder = pointray_io::folder_of(output);
    let mut need = store_need(input_points, folder);
    if merged == MergedTiles::Removed {
        let output_disk = file_system(folder);
        let freed: Vec<u64> = tiles
            .iter()
            .filter_map(|tile| std::fs::metadata(tile).ok())
            .filter(|meta| output_disk == Some(meta.dev()))
            .map(|meta| meta.len())
            .collect();
        let largest = freed.iter().copied().max().unwrap_or(0);
        need.bytes = need.bytes.saturating_sub(freed.iter().sum::<u64>() - largest);
    }
    need
}

/// The files by tile index, once they are seen to be every tile of one cut exactly once.
fn in_tile_order(tiles: &[PathBuf]) -> Result<Vec<PathBuf>, StreamError> {
    let Some(first_path) = tiles.first() else {
        return Err(StreamError::BadTile {
            path: PathBuf::from("(no tile files)"),
            problem: "nothing to merge".into(),
        });
    };
    let first = read_tile_header(first_path)?;
    let mut slots: Vec<Option<PathBuf>> = vec![None; first.count as usize];
    for path in tiles {
        let header = read_tile_header(path)?;
        let mismatch = |what: &str| StreamError::BadTile {
            path: path.clone(),
            problem: format!(
                "{what} differs from {}'s: the tiles come from different preps",
                first_path.display()
            ),
        };
        if header.count != first.count {
            return Err(mismatch("the tile count"));
        }
        if header.input_points != first.input_points {
            return Err(mismatch("the input's point count"));
        }
        if header.neighbor_slots != first.neighbor_slots {
            return Err(mismatch("the colour neighbour count"));
        }
        let slot = &mut slots[header.index as usize];
        if let Some(earlier) = slot.replace(path.clone()) {
            let problem = format!("tile {} of {} is also {}", header.index, header.count, earlier.display());
            return Err(StreamError::BadTile { path: path.clone(), problem });
        }
    }
    if let Some(missing) = slots.iter().position(Option::is_none) {
        let problem = format!("tile {missing} of {} is missing from the merge", first.count);
        return Err(StreamError::BadTile { path: first_path.clone(), problem });
    }
    Ok(slots.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removed_tiles_on_the_outputs_disk_leave_room_for_the_store_but_the_largest() {
        let dir = tempfile::tempdir().unwrap();
        let tiles: Vec<PathBuf> = [1000, 3000, 2000]
            .iter()
            .enumerate()
            .map(|(i, &bytes)| {
                let path = dir.path().join(format!("{i}.tile"));
                std::fs::write(&path, vec![0u8; bytes]).unwrap();
                path
            })
            .collect();
        let output = dir.path().join("out.patches");
        let kept = store_room_need(&output, 1000, &tiles, MergedTiles::Kept);
        assert_eq!(kept.bytes, 28_000);
        let removed = store_room_need(&output, 1000, &tiles, MergedTiles::Removed);
        assert_eq!(removed.bytes, 28_000 - 3000, "all but the largest tile are freed in time");
    }
}
