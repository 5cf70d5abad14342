//! A cloud sorted along its Morton curve in one scratch file of records, with the bounds of
//! each block of consecutive records: a run of the curve covers a compact region, so the
//! points in a box are found by reading only the blocks whose bounds meet it.

use std::fs::File;
use std::ops::Range;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use rayon::prelude::*;

use crate::tiles::halo_test::HaloTest;
use crate::tiles::point_records::{RecordLayout, key_at, record_position};
use crate::tiles::stream_error::StreamError;

/// Records per block of the index.
const BLOCK_POINTS: u64 = 4096;

/// Records each thread decodes at a time.
const DECODE_BATCH: usize = 1 << 16;

/// Blocks each thread reads at a time when gathering the points in a box.
const BLOCKS_AT_A_TIME: usize = 4;

pub(crate) struct SortedPoints {
    path: PathBuf,
    file: File,
    layout: RecordLayout,
    offset: DVec3,
    count: u64,
    /// The local bounds (min, max) of each block of `BLOCK_POINTS` records.
    blocks: Vec<(Vec3, Vec3)>,
    sensor_position: Option<DVec3>,
}

impl SortedPoints {
    /// The sorted records of `path`, laid out as `layout` and recentred by `offset`, with the
    /// bounds of their blocks: a sort kept by `tiles::kept_sort`. The file must hold `count`
    /// whole records, and the bounds one entry per block.
    pub(crate) fn reopen(
        path: &Path,
        (layout, offset, count): (RecordLayout, DVec3, u64),
        blocks: Vec<BlockBounds>,
        sensor_position: Option<DVec3>,
    ) -> Result<Self, String> {
        let file = File::open(path).map_err(|e| e.to_string())?;
        let length = file.metadata().map_err(|e| e.to_string())?.len();
        let expected = count.checked_mul(layout.bytes() as u64);
        if expected != Some(length) {
            return Err(format!("{length} bytes of records, not the {count} points its index counts"));
        }
        if blocks.len() as u64 != count.div_ceil(BLOCK_POINTS) {
            return Err(format!("{} block bounds for {count} points", blocks.len()));
        }
        Ok(Self { path: path.to_path_buf(), file, layout, offset, count, blocks, sensor_position })
    }

    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    pub(crate) fn layout(&self) -> RecordLayout {
        self.layout
    }

    pub(crate) fn blocks(&self) -> &[BlockBounds] {
        &self.blocks
    }

    pub(crate) fn sensor_position(&self) -> Option<DVec3> {
        self.sensor_position
    }

    pub(crate) fn len(&self) -> u64 {
        self.count
    }

    /// The Morton code of the record at sorted position `position`.
    pub(crate) fn code_at(&self, position: u64) -> Result<u64, StreamError> {
        Ok(key_at(&self.file, self.layout.bytes(), position).map_err(|e| self.scratch(e))?.0)
    }

    /// Bytes a record takes.
    pub(crate) fn record_bytes(&self) -> usize {
        self.layout.bytes()
    }

    /// The points at sorted positions `range`, with their input indices, read and decoded a
    /// batch per thread.
    pub(crate) fn read_range(&self, range: Range<u64>) -> Result<(PointCloud, Vec<u32>), StreamError> {
        let size = self.layout.bytes();
        let batches = (range.start..range.end)
            .step_by(DECODE_BATCH)
            .collect::<Vec<u64>>()
            .into_par_iter()
            .map(|first| {
                let count = (DECODE_BATCH as u64).min(range.end - first) as usize;
                let mut bytes = vec![0u8; count * size];
                self.file.read_exact_at(&mut bytes, first * size as u64).map_err(|e| self.scratch(e))?;
                Ok(self.decode(&bytes))
            })
            .collect::<Result<Vec<_>, StreamError>>()?;
        Ok(self.joined(batches))
    }

    /// The points of `records` (whole records, as `near` hands them out), with their input
    /// indices, decoded a batch per thread.
    pub(crate) fn decode_records(&self, records: &[u8]) -> (PointCloud, Vec<u32>) {
        let size = self.layout.bytes();
        self.joined(records.par_chunks(DECODE_BATCH * size).map(|batch| self.decode(batch)).collect())
    }

    /// Decoded batches, one after another.
    fn joined(&self, batches: Vec<(PointCloud, Vec<u32>)>) -> (PointCloud, Vec<u32>) {
        let mut cloud = self.layout.empty_cloud(self.sensor_position);
        let mut indices = Vec::with_capacity(batches.iter().map(|(_, batch)| batch.len()).sum());
        cloud.positions.reserve(indices.capacity());
        for (batch, batch_indices) in batches {
            cloud.append(batch);
            indices.extend(batch_indices);
        }
        (cloud, indices)
    }

    fn decode(&self, records: &[u8]) -> (PointCloud, Vec<u32>) {
        let mut cloud = self.layout.empty_cloud(self.sensor_position);
        let indices = records
            .chunks_exact(self.layout.bytes())
            .map(|record| self.layout.decode_into(record, &mut cloud).1)
            .collect();
        (cloud, indices)
    }

    /// The points of `region` (local coordinates), outside the sorted positions `skip`,
    /// handed to `batch` with their records (in sorted order), at most about `batch_points`
    /// at a time: whoever keeps some needs not read them again. Blocks are read and
    /// filtered in parallel, a few per thread at a time, so the memory held stays bounded.
    pub(crate) fn near(
        &self,
        region: &HaloTest,
        skip: &Range<u64>,
        batch_points: usize,
        mut batch: impl FnMut(&[Vec3], &[u8]),
    ) -> Result<(), StreamError> {
        let meeting: Vec<usize> = (0..self.blocks.len())
            .into_par_iter()
            .filter(|&block| !self.block_within(block, skip) && region.may_reach_box(self.blocks[block]))
            .collect();
        let (mut points, mut records) = (Vec::new(), Vec::new());
        for group in meeting.chunks(BLOCKS_AT_A_TIME * rayon::current_num_threads()) {
            let found: Vec<(Vec<Vec3>, Vec<u8>)> = group
                .par_iter()
                .map(|&block| self.block_points_within(block, region, skip))
                .collect::<Result<_, _>>()?;
            for (block_points, block_records) in found {
                points.extend(block_points);
                records.extend(block_records);
            }
            if points.len() >= batch_points {
                batch(&points, &records);
                points.clear();
                records.clear();
            }
        }
        if !points.is_empty() {
            batch(&points, &records);
        }
        Ok(())
    }

    /// Whether every record of `block` lies in `range`: a tile's own blocks hold no halo,
    /// and reading them again cost as much as the halo's own blocks.
    fn block_within(&self, block: usize, range: &Range<u64>) -> bool {
        let first = block as u64 * BLOCK_POINTS;
        range.start <= first && (first + BLOCK_POINTS).min(self.count) <= range.end
    }

    /// The points of `block` in `region`, outside `skip`, with their records.
    fn block_points_within(
        &self,
        block: usize,
        region: &HaloTest,
        skip: &Range<u64>,
    ) -> Result<(Vec<Vec3>, Vec<u8>), StreamError> {
        let size = self.layout.bytes();
        let first = block as u64 * BLOCK_POINTS;
        let count = BLOCK_POINTS.min(self.count - first);
        let mut bytes = vec![0; count as usize * size];
        self.file.read_exact_at(&mut bytes, first * size as u64).map_err(|e| self.scratch(e))?;
        let mut found = (Vec::new(), Vec::new());
        for (i, record) in bytes.chunks_exact(size).enumerate() {
            let (position, local) = (first + i as u64, (record_position(record) - self.offset).as_vec3());
            if !skip.contains(&position) && region.may_reach(local) {
                found.0.push(local);
                found.1.extend_from_slice(record);
            }
        }
        Ok(found)
    }

    fn scratch(&self, source: std::io::Error) -> StreamError {
        StreamError::scratch(&self.path, source)
    }
}

/// A block's local bounds (min, max).
pub(crate) type BlockBounds = (Vec3, Vec3);

/// The sorted file, written in pieces side by side: each piece is a stretch of consecutive
/// records at a place known in advance, and notes the bounds of the blocks it touches.
pub(crate) struct SortedFile {
    path: PathBuf,
    file: File,
    layout: RecordLayout,
    offset: DVec3,
    count: u64,
}

impl SortedFile {
    /// A file at `path` for `count` records of `layout`, positions recentred by `offset`.
    pub(crate) fn create(
        path: &Path,
        layout: RecordLayout,
        offset: DVec3,
        count: u64,
    ) -> Result<Self, StreamError> {
        let scratch = |e| StreamError::scratch(path, e);
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(scratch)?;
        file.set_len(count * layout.bytes() as u64).map_err(scratch)?;
        Ok(Self { path: path.to_path_buf(), file, layout, offset, count })
    }

    /// Bytes a record takes.
    pub(crate) fn record_bytes(&self) -> usize {
        self.layout.bytes()
    }

    /// A writer of the records from sorted position `first` on, holding `buffer_bytes`.
    pub(crate) fn piece(&self, first: u64, buffer_bytes: usize) -> SortedPiece<'_> {
        let size = self.layout.bytes();
        let capacity = (buffer_bytes / size).max(1) * size;
        SortedPiece {
            file: self,
            first,
            written: 0,
            buffer: Vec::with_capacity(capacity),
            blocks: Vec::new(),
        }
    }

    /// The sorted points, once every piece is written; `pieces` holds the block bounds each
    /// piece noted.
    pub(crate) fn finish(
        self,
        pieces: Vec<Vec<(u64, BlockBounds)>>,
        sensor_position: Option<DVec3>,
    ) -> SortedPoints {
        let Self { path, file, layout, offset, count } = self;
        let empty = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let mut blocks = vec![empty; count.div_ceil(BLOCK_POINTS) as usize];
        for (block, (low, high)) in pieces.into_iter().flatten() {
            let bounds = &mut blocks[block as usize];
            *bounds = (bounds.0.min(low), bounds.1.max(high));
        }
        SortedPoints { path, file, layout, offset, count, blocks, sensor_position }
    }
}

/// One piece of the sorted file, written in order.
pub(crate) struct SortedPiece<'a> {
    file: &'a SortedFile,
    /// The sorted position of the piece's first record.
    first: u64,
    /// Records written out so far.
    written: u64,
    buffer: Vec<u8>,
    /// The bounds of the blocks the piece touches, in order.
    blocks: Vec<(u64, BlockBounds)>,
}

impl SortedPiece<'_> {
    pub(crate) fn push(&mut self, record: &[u8]) -> Result<(), StreamError> {
        let size = self.file.layout.bytes();
        let position = self.first + self.written + (self.buffer.len() / size) as u64;
        let local = (record_position(record) - self.file.offset).as_vec3();
        let block = position / BLOCK_POINTS;
        match self.blocks.last_mut() {
            Some((last, bounds)) if *last == block => *bounds = (bounds.0.min(local), bounds.1.max(local)),
            _ => self.blocks.push((block, (local, local))),
        }
        self.buffer.extend_from_slice(record);
        if self.buffer.len() == self.buffer.capacity() {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes what is buffered and returns the bounds of the blocks the piece touched.
    pub(crate) fn finish(mut self) -> Result<Vec<(u64, BlockBounds)>, StreamError> {
        self.flush()?;
        Ok(self.blocks)
    }

    fn flush(&mut self) -> Result<(), StreamError> {
        let size = self.file.layout.bytes() as u64;
        let at = (self.first + self.written) * size;
        self.file
            .file
            .write_all_at(&self.buffer, at)
            .map_err(|e| StreamError::scratch(&self.file.path, e))?;
        self.written += self.buffer.len() as u64 / size;
        self.buffer.clear();
        Ok(())
    }
}
