//! A compact patch store written in place while its patches are still being made. Each
//! section has room for a bound on the patch count (`Layout::with_room`), so every batch of
//! patches goes straight to its place in the output as it comes, and the disk writes it while
//! later batches are made. Blocks (`compact_patches`) are cut at the same patches whatever
//! the batches: a block a batch leaves unfinished waits in memory for the next. Each block's
//! coarse level (`stored_coarse`) is made as the block is written and held in memory (about
//! 6% of the patches at 44 bytes each), as its place follows the colour neighbours, whose
//! length only the last batch fixes. Finishing writes the last block, the colour neighbours
//! mapped to patches, the coarse level, the header and the checksum: the same store
//! whichever batches its patches came in.

use std::os::unix::fs::FileExt;
use std::path::Path;

use crc32fast::Hasher;
use pointray_io::AtomicFile;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS, PatchCold, PatchHot};
use rayon::prelude::*;

use crate::compact_patches::{BLOCK_PATCHES, BlockFrame, CompactColor, CompactPatch, cold_problem};
use crate::compact_patches::{colors_of, frames_of, patches_of, stored_origin_bounds};
use crate::parallel_checksum::{joined, piece_hasher, zeros_hasher};
use crate::patch_store::{
    Counts, HEADER_BYTES, Layout, NEIGHBOR_SECTION, RecordShape, SECTION_COUNT, Section, StoreError,
};
use crate::patch_store_write::{StoreSummary, header_for, store_error};
use crate::stored_coarse::StoredCoarse;

/// Bytes written or mapped at a time by one thread: a multiple of a colour neighbour's 4, and
/// small, since every thread maps a piece in a buffer of its own.
const PIECE_BYTES: usize = 1 << 20;

/// A patch store being written in place, batch by batch.
pub struct StoreInPlace {
    output: AtomicFile,
    room: u64,
    /// The records' shape and where each section starts, fixed by the first patches.
    placed: Option<(RecordShape, [u64; SECTION_COUNT])>,
    /// Patches appended so far.
    patches: u64,
    /// Patches encoded and written so far: whole blocks, until the store is finished.
    encoded: u64,
    /// The records of the block the last batch left unfinished.
    pending: (Vec<PatchHot>, Vec<PatchCold>),
    /// The checksum of each section's bytes so far; the neighbours' come when mapped.
    hashers: [Hasher; NEIGHBOR_SECTION],
    /// The box of the origins encoded so far, as stored.
    bounds: Option<Aabb>,
    /// The coarse level of the blocks encoded so far.
    coarse: StoredCoarse,
}

impl StoreInPlace {
    /// A store to become `path`, with room for `room` patches.
    pub fn create(path: &Path, room: u64) -> Result<Self, StoreError> {
        let shape = RecordShape::compact(COLOR_NEIGHBORS as u32, true);
        if Layout::with_room(Counts::new(0, 0), room, shape).is_none() {
            let problem = format!("room for {room} patches overflows a file's length");
            return Err(StoreError::InconsistentPatchSet { path: path.to_path_buf(), problem });
        }
        let output = AtomicFile::create(path).map_err(|e| store_error(path, e))?;
        Ok(Self {
            output,
            room,
            placed: None,
            patches: 0,
            encoded: 0,
            pending: Default::default(),
            hashers: Default::default(),
            bounds: None,
            coarse: StoredCoarse::default(),
        })
    }

    /// Writes the records `hot`, `cold` and `color_neighbors` (which name input points)
    /// after those written so far. The first patches fix the colour neighbours per patch; a
    /// store has colour columns when it has colour neighbours.
    pub fn append(
        &mut self,
        hot: &[PatchHot],
        cold: &[PatchCold],
        color_neighbors: &[u32],
    ) -> Result<(), StoreError> {
        let count = hot.len() as u64;
        if count == 0 {
            return Ok(());
        }
        if self.patches + count > self.room {
            let problem = format!("{} patches overflow the room for {}", self.patches + count, self.room);
            return Err(self.inconsistent(problem));
        }
        let slots = (color_neighbors.len() as u64 / count) as u32;
        let (shape, starts) = self.placed(slots)?;
        if shape.neighbor_slots != slots
            || color_neighbors.len() as u64 != count * u64::from(slots)
            || cold.len() != hot.len()
        {
            let problem = "the batches' colour neighbours per patch, or a batch's records, differ in number";
            return Err(self.inconsistent(problem.into()));
        }
        if let Some(problem) = cold_problem(cold, shape.colors) {
            return Err(self.inconsistent(problem));
        }
        let at = starts[NEIGHBOR_SECTION] + self.patches * 4 * u64::from(slots);
        self.write_at(bytemuck::cast_slice(color_neighbors), at).map_err(|e| self.io_error(e))?;
        self.patches += count;
        self.encode(hot, cold)
    }

    /// The shape and section starts, fixed now by a batch of `slots` colour neighbours a patch
    /// if no batch has fixed them yet.
    fn placed(&mut self, slots: u32) -> Result<(RecordShape, [u64; SECTION_COUNT]), StoreError> {
        if let Some(placed) = self.placed {
            return Ok(placed);
        }
        let shape = RecordShape::compact(slots, slots != 0);
        let layout = Layout::with_room(Counts::new(0, 0), self.room, shape)
            .ok_or_else(|| self.inconsistent("no room".into()))?;
        let placed = (shape, layout.sections.map(|section| section.offset));
        self.placed = Some(placed);
        Ok(placed)
    }

    /// Encodes and writes the whole blocks of the pending records followed by `hot` and
    /// `cold`, keeping the rest pending.
    fn encode(&mut self, mut hot: &[PatchHot], mut cold: &[PatchCold]) -> Result<(), StoreError> {
        if !self.pending.0.is_empty() {
            let take = (BLOCK_PATCHES - self.pending.0.len()).min(hot.len());
            self.pending.0.extend_from_slice(&hot[..take]);
            self.pending.1.extend_from_slice(&cold[..take]);
            (hot, cold) = (&hot[take..], &cold[take..]);
            if self.pending.0.len() < BLOCK_PATCHES {
                return Ok(());
            }
            let (pending_hot, pending_cold) = std::mem::take(&mut self.pending);
            self.write_blocks(&pending_hot, &pending_cold)?;
        }
        let whole = hot.len() / BLOCK_PATCHES * BLOCK_PATCHES;
        self.write_blocks(&hot[..whole], &cold[..whole])?;
        self.pending = (hot[whole..].to_vec(), cold[whole..].to_vec());
        Ok(())
    }

    /// Encodes `hot` and `cold`, which start a block, and writes them after those encoded.
    fn write_blocks(&mut self, hot: &[PatchHot], cold: &[PatchCold]) -> Result<(), StoreError> {
        if hot.is_empty() {
            return Ok(());
        }
        let (shape, starts) = self.placed.expect("placed by the first batch");
        let frames = frames_of(hot, cold);
        let ((patches, colors), coarse) = rayon::join(
            || {
                rayon::join(
                    || patches_of(&frames, hot, cold),
                    || if shape.colors { colors_of(cold) } else { Vec::new() },
                )
            },
            || StoredCoarse::of_blocks(&frames, hot, cold, shape.colors),
        );
        self.coarse.extend(coarse);
        let first = self.encoded;
        let block = first / BLOCK_PATCHES as u64;
        let sections: [(&[u8], u64); NEIGHBOR_SECTION] = [
            (bytemuck::cast_slice(&frames), block * size_of::<BlockFrame>() as u64),
            (bytemuck::cast_slice(&patches), first * size_of::<CompactPatch>() as u64),
            (bytemuck::cast_slice(&colors), first * size_of::<CompactColor>() as u64),
        ];
        let hashers: Vec<Hasher> = sections
            .par_iter()
            .zip(starts)
            .map(|(&(bytes, offset), start)| {
                let written = self.write_at(bytes, start + offset)?;
                self.output.start_writeback(start + offset, bytes.len() as u64);
                Ok(written)
            })
            .collect::<std::io::Result<_>>()
            .map_err(|e| self.io_error(e))?;
        for (running, written) in self.hashers.iter_mut().zip(hashers) {
            running.combine(&written);
        }
        self.encoded += hot.len() as u64;
        self.bounds = match (self.bounds, stored_origin_bounds(hot)) {
            (Some(a), Some(b)) => Some(a.union(&b)),
            (a, b) => a.or(b),
        };
        Ok(())
    }

    /// Writes the last block, maps the colour neighbours through `neighbor`, writes the
    /// coarse level, the header of `summary` (whose patches are those appended) and the
    /// checksum, and renames the store into place.
    pub fn finish(
        mut self,
        summary: &StoreSummary,
        neighbor: impl Fn(u32) -> u32 + Sync,
    ) -> Result<(), StoreError> {
        let (shape, _) = self.placed(summary.neighbor_slots)?;
        let (pending_hot, pending_cold) = std::mem::take(&mut self.pending);
        self.write_blocks(&pending_hot, &pending_cold)?;
        let counts = Counts::new(self.patches, self.coarse.records.len() as u64);
        let layout = Layout::with_room(counts, self.room, shape)
            .filter(|_| {
                summary.patches == self.patches
                    && summary.room == self.room
                    && summary.neighbor_slots == shape.neighbor_slots
            })
            .ok_or_else(|| self.inconsistent("the summary is not of the patches written".into()))?;
        let neighbors = self.map_neighbors(layout.sections[NEIGHBOR_SECTION], &neighbor)?;
        let [.., coarse_counts, coarse_records] = layout.sections;
        let coarse = self.write_coarse([coarse_counts, coarse_records])?;
        let header = header_for(summary, &layout, shape, (self.bounds, counts.coarse));
        let mut checksum = piece_hasher(bytemuck::bytes_of(&header));
        let mut position = HEADER_BYTES as u64;
        let hashers = self.hashers.iter().chain([&neighbors]).chain(&coarse);
        for (section, hasher) in layout.sections.iter().zip(hashers) {
            checksum.combine(&zeros_hasher(section.offset - position));
            checksum.combine(hasher);
            position = section.offset + section.length;
        }
        let file = self.output.file();
        file.write_all_at(bytemuck::bytes_of(&header), 0)
            .and_then(|()| file.write_all_at(&checksum.finalize().to_le_bytes(), position))
            .map_err(|e| self.io_error(e))?;
        let target = self.output.target().to_path_buf();
        self.output.commit().map_err(|e| store_error(&target, e))
    }

    /// Writes the coarse level's block counts and records into their `sections`, and
    /// returns their checksums.
    fn write_coarse(&self, [counts, records]: [Section; 2]) -> Result<[Hasher; 2], StoreError> {
        let counts = self.write_at(bytemuck::cast_slice(&self.coarse.counts), counts.offset);
        let records = self.write_at(bytemuck::cast_slice(&self.coarse.records), records.offset);
        Ok([counts.map_err(|e| self.io_error(e))?, records.map_err(|e| self.io_error(e))?])
    }

    /// Rewrites the neighbour section's bytes through `neighbor`, on every core, and returns
    /// their checksum.
    fn map_neighbors(
        &self,
        section: Section,
        neighbor: &(impl Fn(u32) -> u32 + Sync),
    ) -> Result<Hasher, StoreError> {
        let (start, length) = (section.offset, section.length);
        let pieces = length.div_ceil(PIECE_BYTES as u64);
        let file = self.output.file();
        let hashers = (0..pieces)
            .into_par_iter()
            .map(|piece| {
                let at = piece * PIECE_BYTES as u64;
                let mut bytes = vec![0u8; (length - at).min(PIECE_BYTES as u64) as usize];
                file.read_exact_at(&mut bytes, start + at)?;
                for word in bytes.chunks_exact_mut(4) {
                    let mapped = neighbor(u32::from_le_bytes([word[0], word[1], word[2], word[3]]));
                    word.copy_from_slice(&mapped.to_le_bytes());
                }
                file.write_all_at(&bytes, start + at)?;
                Ok(piece_hasher(&bytes))
            })
            .collect::<std::io::Result<Vec<_>>>()
            .map_err(|e| self.io_error(e))?;
        Ok(hashers.into_iter().fold(Hasher::new(), joined))
    }

    /// Writes `bytes` at `at` in pieces on every core, and returns their checksum.
    fn write_at(&self, bytes: &[u8], at: u64) -> std::io::Result<Hasher> {
        let file = self.output.file();
        bytes
            .par_chunks(PIECE_BYTES)
            .enumerate()
            .map(|(i, piece)| {
                file.write_all_at(piece, at + (i * PIECE_BYTES) as u64).map(|()| piece_hasher(piece))
            })
            .try_reduce(Hasher::new, |before, after| Ok(joined(before, after)))
    }

    fn io_error(&self, source: std::io::Error) -> StoreError {
        StoreError::Io { path: self.output.target().to_path_buf(), source }
    }

    fn inconsistent(&self, problem: String) -> StoreError {
        StoreError::InconsistentPatchSet { path: self.output.target().to_path_buf(), problem }
    }
}
