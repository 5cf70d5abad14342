//! The tiles of a prep in tiles within one process, written into the store as they come
//! (`patch_store_in_place`), with room for every input point's patch; each input point's
//! patch is noted, so that the colour neighbours, which name input points, can be mapped to
//! patches once every tile is in. The store is the one `tiles::merge` writes from tile files,
//! byte for byte.

use std::path::Path;

use crate::prep_progress::{PrepProgress, Stage};
use crate::tiles::merge::MergeSummary;
use crate::tiles::patch_map::PatchMap;
use crate::tiles::stream_error::StreamError;
use crate::tiles::tiled_prep::TilePatches;
use glam::DVec3;
use pointray_kernels::{PatchCold, PatchHot};
use pointray_patches::patch_store::StoreSummary;
use pointray_patches::patch_store_in_place::StoreInPlace;
use pointray_patches::{PrepSettings, ScanStructure};

pub(crate) struct TileSpool {
    store: StoreInPlace,
    patch_of: PatchMap,
    summary: StoreSummary,
    tiles: usize,
    input_points: u64,
}

impl TileSpool {
    /// A spool into the store `output` for an input of `input_points` prepped with
    /// `settings` and recentred by `offset`.
    pub(crate) fn new(
        output: &Path,
        input_points: u64,
        (settings, offset): (PrepSettings, DVec3),
    ) -> Result<Self, StreamError> {
        let store = StoreInPlace::create(output, input_points)?;
        let patch_of = PatchMap::new(input_points as usize);
        let summary = StoreSummary {
            settings,
            offset,
            patches: 0,
            room: input_points,
            neighbor_slots: 0,
            scan: ScanStructure::NotRecorded,
        };
        Ok(Self { store, patch_of, summary, tiles: 0, input_points })
    }

    /// Appends the next tile along the curve.
    pub(crate) fn push(&mut self, tile: &TilePatches) -> Result<(), StreamError> {
        let set = &tile.patches;
        self.push_records((&set.hot, &set.cold, &set.color_neighbors), &tile.sources)
    }

    /// Appends the next tile's records (hot, cold, colour neighbours naming input points),
    /// each patch made from the input point `sources` names.
    pub(crate) fn push_records(
        &mut self,
        (hot, cold, color_neighbors): (&[PatchHot], &[PatchCold], &[u32]),
        sources: &[u32],
    ) -> Result<(), StreamError> {
        let total = &mut self.summary;
        if !sources.is_empty() {
            total.neighbor_slots = (color_neighbors.len() / sources.len()) as u32;
        }
        let first_patch = total.patches;
        total.patches += sources.len() as u64;
        let patch_of = &mut self.patch_of;
        let store = &mut self.store;
        // The records go to disk while the map is filled.
        let (_, written) =
            rayon::join(|| patch_of.note(sources, first_patch), || store.append(hot, cold, color_neighbors));
        written?;
        self.tiles += 1;
        Ok(())
    }

    /// Finishes the store: the colour neighbours mapped to patches, the header and the
    /// checksum; it then replaces the output atomically.
    pub(crate) fn write_store(self, progress: &dyn PrepProgress) -> Result<MergeSummary, StreamError> {
        progress.stage_started(Stage::MergeTiles, self.summary.patches);
        let started = std::time::Instant::now();
        let written = self.finish()?;
        progress.advanced(written.patches);
        progress.stage_finished(Stage::MergeTiles, started.elapsed());
        Ok(written)
    }

    /// `write_store` without its progress, for a merge whose stage spans the tiles' reading.
    pub(crate) fn finish(self) -> Result<MergeSummary, StreamError> {
        let Self { store, patch_of, summary, tiles, input_points } = self;
        store.finish(&summary, |input| patch_of.patch(input))?;
        Ok(MergeSummary { tiles, input_points, patches: summary.patches })
    }

    /// The settings and offset the tiles were prepped with.
    pub(crate) fn frame(&self) -> (PrepSettings, DVec3) {
        (self.summary.settings, self.summary.offset)
    }
}
