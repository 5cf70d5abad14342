//! A patch store written in place while its patches are still being made. Each section has
//! room for a bound on the patch count (`Layout::with_room`), so every batch of patches goes
//! straight to its place in the output as it comes, and the disk writes it while later
//! batches are made. Finishing writes only the header, the colour neighbours mapped to
//! patches, and the checksum: the store `patch_store_write::write_sections` writes with the
//! same room, byte for byte.

use std::os::unix::fs::FileExt;
use std::path::Path;

use crc32fast::Hasher;
use pointray_io::AtomicFile;
use rayon::prelude::*;

use crate::parallel_checksum::{joined, piece_hasher, zeros_hasher};
use crate::patch_set::PatchSet;
use crate::patch_store::{HEADER_BYTES, Layout, SECTION_COUNT, StoreError};
use crate::patch_store_write::{StoreSummary, header_for, store_error};

/// The section of colour neighbours, which name input points until the store is finished.
const NEIGHBOR_SECTION: usize = 3;

/// Bytes written or mapped at a time by one thread: a multiple of a colour neighbour's 4, and
/// small, since every thread maps a piece in a buffer of its own.
const PIECE_BYTES: usize = 1 << 20;

/// A patch store being written in place, batch by batch.
pub struct StoreInPlace {
    output: AtomicFile,
    room: u64,
    /// Where each section starts.
    starts: [u64; SECTION_COUNT],
    /// Patches written so far.
    patches: u64,
    /// The checksum of each section's bytes so far; the neighbours' come when mapped.
    hashers: [Hasher; NEIGHBOR_SECTION],
}

impl StoreInPlace {
    /// A store to become `path`, with room for `room` patches.
    pub fn create(path: &Path, room: u64) -> Result<Self, StoreError> {
        let overflow = || StoreError::InconsistentPatchSet {
            path: path.to_path_buf(),
            problem: format!("room for {room} patches overflows a file's length"),
        };
        let layout = Layout::with_room(0, room, 0).ok_or_else(overflow)?;
        let output = AtomicFile::create(path).map_err(|e| store_error(path, e))?;
        let starts = layout.sections.map(|section| section.offset);
        Ok(Self { output, room, starts, patches: 0, hashers: Default::default() })
    }

    /// Writes `set`'s records after those written so far, its colour neighbours naming input
    /// points.
    pub fn append(&mut self, set: &PatchSet) -> Result<(), StoreError> {
        let count = set.len() as u64;
        if self.patches + count > self.room {
            let problem = format!("{} patches overflow the room for {}", self.patches + count, self.room);
            return Err(self.inconsistent(problem));
        }
        let sections: [&[u8]; SECTION_COUNT] = [
            bytemuck::cast_slice(&set.aabbs),
            bytemuck::cast_slice(&set.hot),
            bytemuck::cast_slice(&set.cold),
            bytemuck::cast_slice(&set.color_neighbors),
        ];
        let first = self.patches;
        let hashers: Vec<Hasher> = (0..SECTION_COUNT)
            .into_par_iter()
            .map(|index| {
                let bytes = sections[index];
                let at = self.starts[index] + first * (bytes.len() as u64 / count.max(1));
                let written = self.write_at(bytes, at)?;
                if index != NEIGHBOR_SECTION {
                    self.output.start_writeback(at, bytes.len() as u64);
                }
                Ok(written)
            })
            .collect::<std::io::Result<_>>()
            .map_err(|e| self.io_error(e))?;
        for (running, written) in self.hashers.iter_mut().zip(hashers) {
            running.combine(&written);
        }
        self.patches += count;
        Ok(())
    }

    /// Maps the colour neighbours through `neighbor`, writes the header of `summary` (whose
    /// patches are those appended) and the checksum, and renames the store into place.
    pub fn finish(
        self,
        summary: &StoreSummary,
        neighbor: impl Fn(u32) -> u32 + Sync,
    ) -> Result<(), StoreError> {
        let layout = Layout::with_room(self.patches, self.room, summary.neighbor_slots)
            .filter(|_| summary.patches == self.patches && summary.room == self.room)
            .ok_or_else(|| self.inconsistent("the summary is not of the patches written".into()))?;
        let neighbors = self.map_neighbors(layout.sections[NEIGHBOR_SECTION].length, &neighbor)?;
        let header = header_for(summary, &layout);
        let mut checksum = piece_hasher(bytemuck::bytes_of(&header));
        let mut position = HEADER_BYTES as u64;
        for (section, hasher) in layout.sections.iter().zip(self.hashers.iter().chain([&neighbors])) {
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

    /// Rewrites the neighbour section's `length` bytes through `neighbor`, on every core,
    /// and returns their checksum.
    fn map_neighbors(
        &self,
        length: u64,
        neighbor: &(impl Fn(u32) -> u32 + Sync),
    ) -> Result<Hasher, StoreError> {
        let start = self.starts[NEIGHBOR_SECTION];
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
