//! A cloud sorted along its Morton curve in one scratch file of records, with the bounds of
//! each block of consecutive records: a run of the curve covers a compact region, so the
//! points in a box are found by reading only the blocks whose bounds meet it.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::ops::Range;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use pointray_io::PointCloud;
use rayon::prelude::*;

use crate::halo_test::HaloTest;
use crate::point_records::{RecordLayout, record_key, record_position};
use crate::stream_error::StreamError;

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
    pub(crate) fn len(&self) -> u64 {
        self.count
    }

    /// Bytes a record takes.
    pub(crate) fn record_bytes(&self) -> usize {
        self.layout.bytes()
    }

    /// The points at sorted positions `range`, with their input indices.
    pub(crate) fn read_range(&self, range: Range<u64>) -> Result<(PointCloud, Vec<u32>), StreamError> {
        let size = self.layout.bytes() as u64;
        let mut bytes = vec![0u8; ((range.end - range.start) * size) as usize];
        self.file.read_exact_at(&mut bytes, range.start * size).map_err(|e| self.scratch(e))?;
        Ok(self.decode_records(&bytes))
    }

    /// The points of `records` (whole records, as `near` hands them out), with their input
    /// indices, decoded a batch per thread.
    pub(crate) fn decode_records(&self, records: &[u8]) -> (PointCloud, Vec<u32>) {
        let size = self.layout.bytes();
        let batches: Vec<(PointCloud, Vec<u32>)> =
            records.par_chunks(DECODE_BATCH * size).map(|batch| self.decode(batch)).collect();
        let mut cloud = self.layout.empty_cloud(self.sensor_position);
        let mut indices = Vec::with_capacity(records.len() / size);
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
            .filter(|&block| region.may_reach_box(self.blocks[block]))
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

/// Writes the sorted file record by record, keeping the block bounds.
pub(crate) struct SortedWriter {
    path: PathBuf,
    out: BufWriter<File>,
    layout: RecordLayout,
    offset: DVec3,
    count: u64,
    blocks: Vec<(Vec3, Vec3)>,
    last_key: Option<(u64, u32)>,
}

impl SortedWriter {
    pub(crate) fn create(path: &Path, layout: RecordLayout, offset: DVec3) -> Result<Self, StreamError> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| StreamError::scratch(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            out: BufWriter::with_capacity(1 << 20, file),
            layout,
            offset,
            count: 0,
            blocks: Vec::new(),
            last_key: None,
        })
    }

    pub(crate) fn push(&mut self, record: &[u8]) -> Result<(), StreamError> {
        let key = record_key(record);
        debug_assert!(self.last_key.is_none_or(|last| last < key), "records arrive in order");
        self.last_key = Some(key);
        let local = (record_position(record) - self.offset).as_vec3();
        if self.count.is_multiple_of(BLOCK_POINTS) {
            self.blocks.push((local, local));
        }
        let block = self.blocks.last_mut().expect("a block was opened");
        *block = (block.0.min(local), block.1.max(local));
        self.count += 1;
        self.out.write_all(record).map_err(|e| StreamError::scratch(&self.path, e))
    }

    pub(crate) fn finish(self, sensor_position: Option<DVec3>) -> Result<SortedPoints, StreamError> {
        let Self { path, out, layout, offset, count, blocks, .. } = self;
        let file = out.into_inner().map_err(|e| StreamError::scratch(&path, e.into_error()))?;
        Ok(SortedPoints { path, file, layout, offset, count, blocks, sensor_position })
    }
}
