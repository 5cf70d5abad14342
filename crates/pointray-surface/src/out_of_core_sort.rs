//! Sorting a cloud along its Morton curve out of core: runs of points that fit the budget
//! are sorted in memory and written to scratch files, then merged into one sorted file
//! (`SortedPoints`). The order is `morton_order`'s over the whole cloud: by code, ties in
//! input order.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fs::File;
use std::io::{BufReader, Read, Write};
use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_io::{PointCloud, PointStream};
use rayon::prelude::*;

use crate::morton::MortonGrid;
use crate::point_records::{RecordKey, RecordLayout, record_key};
use crate::prep_progress::{PrepProgress, Stage};
use crate::sorted_points::{SortedPoints, SortedWriter};
use crate::stream_error::StreamError;

/// Points each thread encodes at a time.
const ENCODE_BATCH: usize = 1 << 14;

/// Bytes of records a sorted run gathers in order, in parallel, before writing them: small
/// beside any budget, large enough to share among threads.
const WRITE_BATCH_BYTES: usize = 1 << 20;

/// Buffered bytes per run while merging.
const MERGE_BUFFER_BYTES: usize = 256 << 10;

/// How a cloud is sorted: the curve, the recentring and the memory each part may take.
pub(crate) struct SortPlan<'a> {
    pub grid: MortonGrid,
    pub offset: DVec3,
    /// Points read at a time.
    pub chunk_points: usize,
    /// Bytes of records sorted in memory at a time.
    pub run_bytes: usize,
    pub folder: &'a Path,
}

/// Sorts `stream`'s points into `plan.folder`.
pub(crate) fn sort_points(
    stream: &mut PointStream,
    plan: &SortPlan,
    progress: &dyn PrepProgress,
) -> Result<SortedPoints, StreamError> {
    progress.stage_started(Stage::SortRuns, stream.len());
    let started = std::time::Instant::now();
    let mut runs = Runs { plan, layout: None, records: Vec::new(), files: Vec::new(), read: 0 };
    stream.read(plan.chunk_points, |chunk| {
        progress.advanced(chunk.len() as u64);
        runs.add(&chunk)
    })?;
    runs.flush()?;
    progress.stage_finished(Stage::SortRuns, started.elapsed());
    let Runs { layout, files, read, .. } = runs;
    let layout = layout.unwrap_or_default();
    let sorted = merge_runs(&files, layout, plan, read, stream.sensor_position(), progress)?;
    files.iter().for_each(|file| {
        let _ = std::fs::remove_file(file);
    });
    Ok(sorted)
}

/// The run being filled and the runs written.
struct Runs<'a> {
    plan: &'a SortPlan<'a>,
    layout: Option<RecordLayout>,
    records: Vec<u8>,
    files: Vec<PathBuf>,
    read: u64,
}

impl Runs<'_> {
    fn add(&mut self, chunk: &PointCloud) -> Result<(), StreamError> {
        let layout = *self.layout.get_or_insert_with(|| RecordLayout::of(chunk));
        assert_eq!(layout, RecordLayout::of(chunk), "every chunk of a stream carries the same attributes");
        let first = self.read;
        let (grid, offset) = (self.plan.grid, self.plan.offset);
        let encoded: Vec<Vec<u8>> = (0..chunk.len())
            .into_par_iter()
            .chunks(ENCODE_BATCH)
            .map(|batch| {
                let mut records = Vec::with_capacity(batch.len() * layout.bytes());
                for i in batch {
                    let code = grid.code((chunk.positions[i] - offset).as_vec3());
                    layout.encode(chunk, i, (code, (first + i as u64) as u32), &mut records);
                }
                records
            })
            .collect();
        encoded.iter().for_each(|records| self.records.extend_from_slice(records));
        self.read += chunk.len() as u64;
        if self.records.len() >= self.plan.run_bytes {
            self.flush()?;
        }
        Ok(())
    }

    /// Sorts the run in memory and writes it out.
    fn flush(&mut self) -> Result<(), StreamError> {
        let Some(layout) = self.layout else { return Ok(()) };
        if self.records.is_empty() {
            return Ok(());
        }
        let size = layout.bytes();
        let mut keyed: Vec<(RecordKey, u32)> =
            self.records.par_chunks_exact(size).enumerate().map(|(i, r)| (record_key(r), i as u32)).collect();
        keyed.par_sort_unstable();
        let path = self.plan.folder.join(format!("run-{}", self.files.len()));
        let scratch = |e| StreamError::scratch(&path, e);
        let mut out = File::create(&path).map_err(scratch)?;
        let mut ordered = Vec::new();
        for part in keyed.chunks((WRITE_BATCH_BYTES / size).max(1)) {
            ordered.resize(part.len() * size, 0);
            ordered.par_chunks_exact_mut(size).zip(part).for_each(|(slot, &(_, i))| {
                let start = i as usize * size;
                slot.copy_from_slice(&self.records[start..start + size]);
            });
            out.write_all(&ordered).map_err(scratch)?;
        }
        self.files.push(path);
        self.records.clear();
        Ok(())
    }
}

/// Merges the sorted runs into one sorted file with its block index.
fn merge_runs(
    files: &[PathBuf],
    layout: RecordLayout,
    plan: &SortPlan,
    count: u64,
    sensor_position: Option<DVec3>,
    progress: &dyn PrepProgress,
) -> Result<SortedPoints, StreamError> {
    progress.stage_started(Stage::MergeRuns, count);
    let started = std::time::Instant::now();
    let size = layout.bytes();
    let path = plan.folder.join("sorted");
    let mut writer = SortedWriter::create(&path, layout, plan.offset)?;
    let mut readers = files
        .iter()
        .map(|file| {
            File::open(file)
                .map(|f| BufReader::with_capacity(MERGE_BUFFER_BYTES, f))
                .map_err(|e| StreamError::scratch(file, e))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut heads = vec![vec![0u8; size]; files.len()];
    let mut heap = BinaryHeap::new();
    for (run, reader) in readers.iter_mut().enumerate() {
        if next_record(reader, &mut heads[run], &files[run])? {
            heap.push(Reverse((record_key(&heads[run]), run)));
        }
    }
    let mut merged = 0u64;
    while let Some(Reverse((_, run))) = heap.pop() {
        writer.push(&heads[run])?;
        merged += 1;
        if merged.is_multiple_of(1 << 16) {
            progress.advanced(1 << 16);
        }
        if next_record(&mut readers[run], &mut heads[run], &files[run])? {
            heap.push(Reverse((record_key(&heads[run]), run)));
        }
    }
    let sorted = writer.finish(sensor_position)?;
    progress.stage_finished(Stage::MergeRuns, started.elapsed());
    Ok(sorted)
}

/// Reads the next record of a run into `record`; false at the run's end.
fn next_record(reader: &mut impl Read, record: &mut [u8], path: &Path) -> Result<bool, StreamError> {
    match reader.read_exact(record) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(false),
        Err(e) => Err(StreamError::scratch(path, e)),
    }
}
