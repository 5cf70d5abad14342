//! The tiles of a prep in tiles within one process, spooled as they come: each of the
//! store's sections (boxes, hot and cold records, colour neighbours by input point) goes to
//! a scratch file of its own, and each input point's patch is noted. The store is then those
//! files copied in order, once each, with the neighbours mapped to patches: the store
//! `tile_merge` writes from tile files, byte for byte, without reading each tile back once
//! per section.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_kernels::NO_NEIGHBOR;
use rayon::prelude::*;

use crate::patch_store::{self, StoreSummary};
use crate::prep_progress::{PrepProgress, Stage};
use crate::prep_settings::PrepSettings;
use crate::stream_error::StreamError;
use crate::tile_merge::MergeSummary;
use crate::tiled_prep::TilePatches;

/// The store's sections: boxes, hot records, cold records, colour neighbours.
const SECTIONS: usize = 4;

/// Bytes buffered per section file.
const BUFFER_BYTES: usize = 4 << 20;

pub(crate) struct TileSpool {
    paths: Vec<PathBuf>,
    files: Vec<BufWriter<File>>,
    /// Each input point's patch, `NO_NEIGHBOR` for points merged away.
    patch_of: Vec<u32>,
    summary: StoreSummary,
    tiles: usize,
    input_points: u64,
}

impl TileSpool {
    /// A spool in `folder` (which it fills with its files) for an input of `input_points`
    /// prepped with `settings` and recentred by `offset`.
    pub(crate) fn new(
        folder: &Path,
        input_points: u64,
        (settings, offset): (PrepSettings, DVec3),
    ) -> Result<Self, StreamError> {
        let paths: Vec<PathBuf> = (0..SECTIONS).map(|i| folder.join(format!("section-{i}"))).collect();
        let files = paths
            .iter()
            .map(|path| {
                File::create_new(path)
                    .map(|file| BufWriter::with_capacity(BUFFER_BYTES, file))
                    .map_err(|e| StreamError::scratch(path, e))
            })
            .collect::<Result<_, _>>()?;
        let patch_of = vec![NO_NEIGHBOR; input_points as usize];
        let summary = StoreSummary { settings, offset, bounds: None, patches: 0, neighbor_slots: 0 };
        Ok(Self { paths, files, patch_of, summary, tiles: 0, input_points })
    }

    /// Appends the next tile along the curve.
    pub(crate) fn push(&mut self, tile: TilePatches) -> Result<(), StreamError> {
        let TilePatches { patches: set, sources } = tile;
        let total = &mut self.summary;
        if !sources.is_empty() {
            total.neighbor_slots = (set.color_neighbors.len() / sources.len()) as u32;
        }
        let first_patch = total.patches;
        total.patches += set.len() as u64;
        total.bounds = match (total.bounds, set.bounds()) {
            (Some(a), Some(b)) => Some(a.union(&b)),
            (a, b) => a.or(b),
        };
        let sections: [&[u8]; SECTIONS] = [
            bytemuck::cast_slice(&set.aabbs),
            bytemuck::cast_slice(&set.hot),
            bytemuck::cast_slice(&set.cold),
            bytemuck::cast_slice(&set.color_neighbors),
        ];
        let patch_of = &mut self.patch_of;
        // Each section goes to its own file, so they are written side by side.
        let (_, written) = rayon::join(
            || {
                for (patch, &input) in sources.iter().enumerate() {
                    patch_of[input as usize] = (first_patch + patch as u64) as u32;
                }
            },
            || {
                self.files.par_iter_mut().zip(&self.paths).zip(sections).try_for_each(
                    |((file, path), bytes)| file.write_all(bytes).map_err(|e| StreamError::scratch(path, e)),
                )
            },
        );
        written?;
        self.tiles += 1;
        Ok(())
    }

    /// Writes the store `output` from the spooled sections, atomically.
    pub(crate) fn write_store(
        self,
        output: &Path,
        progress: &dyn PrepProgress,
    ) -> Result<MergeSummary, StreamError> {
        let Self { paths, files, patch_of, summary, tiles, input_points } = self;
        for (mut file, path) in files.into_iter().zip(&paths) {
            file.flush().map_err(|e| StreamError::scratch(path, e))?;
        }
        progress.stage_started(Stage::MergeTiles, summary.patches);
        let started = std::time::Instant::now();
        let sections: [PathBuf; SECTIONS] = paths.try_into().expect("one file per section");
        patch_store::write_section_files(output, &summary, &sections, |input| {
            patch_of.get(input as usize).copied().unwrap_or(NO_NEIGHBOR)
        })?;
        progress.advanced(summary.patches);
        progress.stage_finished(Stage::MergeTiles, started.elapsed());
        Ok(MergeSummary { tiles, input_points, patches: summary.patches })
    }
}
