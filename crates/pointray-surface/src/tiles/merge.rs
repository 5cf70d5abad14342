//! Tile files merged into one patch store, tile by tile through the writer a single process
//! uses (`StoreInPlace`), so that no more than one tile's patches and a map from input points
//! to patches are in memory at once: the store a single process prepping the same tiles
//! writes, byte for byte. Where a disk cannot hold the tile files and the store at once, the
//! merge can remove each tile file as soon as its records are in the store.

use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use pointray_io::MemoryBudget;
use pointray_patches::ScanStructure;
use pointray_patches::patch_store::StoreSummary;
use pointray_patches::patch_store_in_place::StoreInPlace;

use crate::prep_progress::{PrepProgress, Stage};
use crate::tiles::disk_room::{Need, ensure_room, store_need};
use crate::tiles::patch_map::PatchMap;
use crate::tiles::stream_budget::{STORE_BYTES_PER_POINT, StreamBudget};
use crate::tiles::stream_error::StreamError;
use crate::tiles::tile_file::{read_tile_file, read_tile_header};

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

/// Merges tile files already in order (at least one) into the store `output`.
pub(crate) fn merge_ordered_tile_files(
    ordered: &[PathBuf],
    output: &Path,
    (memory, merged): (MemoryBudget, MergedTiles),
    progress: &dyn PrepProgress,
) -> Result<MergeSummary, StreamError> {
    let first = read_tile_header(&ordered[0])?;
    if !StreamBudget::new(memory, 0).holds_store_writing(first.input_points) {
        let problem = format!(
            "merging tiles of {} points maps each to its patch and holds the coarse level \
             ({STORE_BYTES_PER_POINT} bytes a point), which the memory budget cannot hold",
            first.input_points
        );
        return Err(StreamError::OverBudget { path: output.to_path_buf(), problem });
    }
    progress.stage_started(Stage::MergeTiles, first.input_points);
    let started = std::time::Instant::now();
    let (summary, patch_of) = survey_tiles(ordered, first.input_points, progress)?;
    ensure_room(&[store_room_need(output, first.input_points, ordered, merged)])?;
    let mut store = StoreInPlace::create(output, summary.room)?;
    for path in ordered {
        store.append(&read_tile_file(path)?.1.patches)?;
        if merged == MergedTiles::Removed {
            std::fs::remove_file(path).map_err(|e| StreamError::scratch(path, e))?;
        }
    }
    store.finish(&summary, |input| patch_of.patch(input))?;
    progress.stage_finished(Stage::MergeTiles, started.elapsed());
    Ok(MergeSummary { tiles: ordered.len(), input_points: first.input_points, patches: summary.patches })
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
        let disk = |path: &Path| std::fs::metadata(path).ok().map(|meta| meta.dev());
        let freed: Vec<u64> = tiles
            .iter()
            .filter(|tile| disk(tile).is_some_and(|d| Some(d) == disk(folder)))
            .filter_map(|tile| std::fs::metadata(tile).ok().map(|meta| meta.len()))
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

/// The store's header from every tile and each of the `input_points` input points' patch,
/// with every tile file checked whole; tiles must agree on the settings and the offset.
fn survey_tiles(
    ordered: &[PathBuf],
    input_points: u64,
    progress: &dyn PrepProgress,
) -> Result<(StoreSummary, PatchMap), StreamError> {
    let mut summary: Option<StoreSummary> = None;
    let mut patch_of = PatchMap::new(input_points as usize);
    for path in ordered {
        let (header, tile) = read_tile_file(path)?;
        let set = &tile.patches;
        let total = summary.get_or_insert(StoreSummary {
            settings: set.settings,
            offset: set.offset,
            patches: 0,
            room: header.input_points,
            neighbor_slots: header.neighbor_slots,
            scan: ScanStructure::NotRecorded,
        });
        if set.settings != total.settings || set.offset != total.offset {
            let problem = format!(
                "its prep settings or offset differ from {}'s: the tiles come from different preps",
                ordered[0].display()
            );
            return Err(StreamError::BadTile { path: path.clone(), problem });
        }
        patch_of.note(&tile.sources, total.patches);
        total.add(set);
        progress.advanced(tile.sources.len() as u64);
    }
    Ok((summary.expect("at least one tile"), patch_of))
}
