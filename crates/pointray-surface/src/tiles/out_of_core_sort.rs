//! Sorting a cloud along its Morton curve out of core: runs of points that fit the budget
//! are sorted in memory and written to scratch files, then merged into one sorted file
//! (`SortedPoints`). The order is `morton_order`'s over the whole cloud: by code, ties in
//! input order.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fs::File;
use std::ops::Range;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use glam::DVec3;
use pointray_io::{PointCloud, PointStream};
use rayon::prelude::*;

use crate::morton::MortonGrid;
use crate::prep_progress::{PrepProgress, Stage};
use crate::tiles::point_records::{RecordKey, RecordLayout, key_at, record_key};
use crate::tiles::sorted_points::{BlockBounds, SortedFile, SortedPiece, SortedPoints};
use crate::tiles::stream_error::StreamError;

/// Points each thread encodes at a time.
const ENCODE_BATCH: usize = 1 << 14;

/// Bytes of records each thread gathers in sorted order and writes in its place in the run:
/// small beside any budget, large enough to keep the writes few.
const WRITE_BATCH_BYTES: usize = 1 << 20;

/// Buffered bytes per run and per piece while merging, at most.
const MERGE_BUFFER_BYTES: usize = 256 << 10;

/// Pieces the merge is cut into per thread, so that pieces of uneven length still keep every
/// core busy.
const MERGE_PIECES_PER_THREAD: usize = 4;

/// Keys sampled from each run per piece, to place the pieces' bounds.
const SAMPLES_PER_PIECE: usize = 8;

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
    let Runs { layout, files, .. } = runs;
    let layout = layout.unwrap_or_default();
    let sorted = merge_runs(&files, layout, plan, stream.sensor_position(), progress)?;
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
        let (grid, offset, size) = (self.plan.grid, self.plan.offset, layout.bytes());
        let start = self.records.len();
        self.records.resize(start + chunk.len() * size, 0);
        // Each thread encodes a batch into its own place in the run.
        self.records[start..].par_chunks_mut(ENCODE_BATCH * size).enumerate().for_each(|(batch, out)| {
            let mut records = Vec::with_capacity(out.len());
            for i in batch * ENCODE_BATCH..batch * ENCODE_BATCH + out.len() / size {
                let code = grid.code((chunk.positions[i] - offset).as_vec3());
                layout.encode(chunk, i, (code, (first + i as u64) as u32), &mut records);
            }
            out.copy_from_slice(&records);
        });
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
        let out = File::create(&path).map_err(scratch)?;
        // Each thread gathers a batch of the sorted run and writes it in its place.
        let batch = (WRITE_BATCH_BYTES / size).max(1);
        keyed
            .par_chunks(batch)
            .enumerate()
            .try_for_each(|(part, keys)| {
                let mut ordered = Vec::with_capacity(keys.len() * size);
                for &(_, i) in keys {
                    ordered.extend_from_slice(&self.records[i as usize * size..(i as usize + 1) * size]);
                }
                out.write_all_at(&ordered, (part * batch * size) as u64)
            })
            .map_err(scratch)?;
        self.files.push(path);
        self.records.clear();
        Ok(())
    }
}

/// Merges the sorted runs into one sorted file with its block index. The merge is cut into
/// pieces by keys sampled from the runs; each piece merges its stretch of every run into its
/// own place in the file, on every core.
fn merge_runs(
    files: &[PathBuf],
    layout: RecordLayout,
    plan: &SortPlan,
    sensor_position: Option<DVec3>,
    progress: &dyn PrepProgress,
) -> Result<SortedPoints, StreamError> {
    let size = layout.bytes();
    let runs = files.iter().map(|path| Run::open(path, size)).collect::<Result<Vec<_>, _>>()?;
    let count: u64 = runs.iter().map(|run| run.records).sum();
    progress.stage_started(Stage::MergeRuns, count);
    let started = std::time::Instant::now();
    let pieces = piece_starts(&runs, rayon::current_num_threads() * MERGE_PIECES_PER_THREAD)?;
    let sorted = SortedFile::create(&plan.folder.join("sorted"), layout, plan.offset, count)?;
    let buffer_bytes =
        (plan.run_bytes / (rayon::current_num_threads() * (runs.len() + 1))).clamp(size, MERGE_BUFFER_BYTES);
    let blocks = pieces
        .par_windows(2)
        .map(|piece| {
            let first = piece[0].iter().sum();
            let out = sorted.piece(first, buffer_bytes);
            let merged = merge_piece(&runs, (&piece[0], &piece[1]), out, buffer_bytes)?;
            progress.advanced(piece[1].iter().sum::<u64>() - first);
            Ok(merged)
        })
        .collect::<Result<Vec<_>, StreamError>>()?;
    let sorted = sorted.finish(blocks, sensor_position);
    progress.stage_finished(Stage::MergeRuns, started.elapsed());
    Ok(sorted)
}

/// Where each piece of the merge starts in each run, then every run's end: the pieces' keys
/// split a sample of keys from every run evenly.
fn piece_starts(runs: &[Run], pieces: usize) -> Result<Vec<Vec<u64>>, StreamError> {
    let per_run = (pieces * SAMPLES_PER_PIECE) as u64;
    let sampled = runs
        .par_iter()
        .map(|run| (0..per_run.min(run.records)).map(|i| run.key_at(i * run.records / per_run)).collect())
        .collect::<Result<Vec<Vec<RecordKey>>, StreamError>>()?;
    let mut samples = sampled.concat();
    samples.sort_unstable();
    let mut splitters: Vec<RecordKey> =
        (1..pieces).filter_map(|j| samples.get(j * samples.len() / pieces).copied()).collect();
    splitters.dedup();
    let inner = splitters
        .par_iter()
        .map(|&key| runs.iter().map(|run| run.first_not_below(key)).collect())
        .collect::<Result<Vec<Vec<u64>>, StreamError>>()?;
    let mut starts = vec![vec![0; runs.len()]];
    starts.extend(inner);
    starts.push(runs.iter().map(|run| run.records).collect());
    Ok(starts)
}

/// Merges the stretch `from[r]..to[r]` of every run `r` into `out`.
fn merge_piece(
    runs: &[Run],
    (from, to): (&[u64], &[u64]),
    mut out: SortedPiece,
    buffer_bytes: usize,
) -> Result<Vec<(u64, BlockBounds)>, StreamError> {
    let mut cursors = runs
        .iter()
        .zip(from.iter().zip(to))
        .map(|(run, (&start, &end))| RunCursor::new(run, start..end, buffer_bytes))
        .collect::<Result<Vec<_>, _>>()?;
    let mut heap: BinaryHeap<Reverse<(RecordKey, usize)>> = cursors
        .iter()
        .enumerate()
        .filter_map(|(run, cursor)| cursor.current().map(|record| Reverse((record_key(record), run))))
        .collect();
    while let Some(Reverse((_, run))) = heap.pop() {
        let cursor = &mut cursors[run];
        out.push(cursor.current().expect("a run in the heap has a record"))?;
        if let Some(record) = cursor.advance()? {
            heap.push(Reverse((record_key(record), run)));
        }
    }
    out.finish()
}

/// A sorted run on disk.
struct Run<'a> {
    path: &'a Path,
    file: File,
    record_bytes: usize,
    records: u64,
}

impl<'a> Run<'a> {
    fn open(path: &'a Path, record_bytes: usize) -> Result<Self, StreamError> {
        let scratch = |e| StreamError::scratch(path, e);
        // Writable, so that what the merge has read can be given back.
        let file = std::fs::OpenOptions::new().read(true).write(true).open(path).map_err(scratch)?;
        let records = file.metadata().map_err(scratch)?.len() / record_bytes as u64;
        Ok(Self { path, file, record_bytes, records })
    }

    fn read_at(&self, buffer: &mut [u8], record: u64) -> Result<(), StreamError> {
        self.file
            .read_exact_at(buffer, record * self.record_bytes as u64)
            .map_err(|e| StreamError::scratch(self.path, e))
    }

    /// Gives the disk (or memory) of the bytes `bytes` back: the merge reads each record once,
    /// so the runs shrink as the sorted file grows and the scratch peaks near one copy of the
    /// points, not two. Where the file system cannot, the runs keep their room until removed.
    fn release(&self, bytes: Range<u64>) {
        let flags = rustix::fs::FallocateFlags::PUNCH_HOLE | rustix::fs::FallocateFlags::KEEP_SIZE;
        let _ = rustix::fs::fallocate(&self.file, flags, bytes.start, bytes.end - bytes.start);
    }

    fn key_at(&self, record: u64) -> Result<RecordKey, StreamError> {
        key_at(&self.file, self.record_bytes, record).map_err(|e| StreamError::scratch(self.path, e))
    }

    /// The first record whose key is not below `key` (binary search).
    fn first_not_below(&self, key: RecordKey) -> Result<u64, StreamError> {
        let (mut low, mut high) = (0, self.records);
        while low < high {
            let middle = low + (high - low) / 2;
            if self.key_at(middle)? < key {
                low = middle + 1;
            } else {
                high = middle;
            }
        }
        Ok(low)
    }
}

/// File systems free whole blocks of this size or its multiples; a hole punched across part
/// of one only zeroes it.
const RELEASE_ALIGN: u64 = 4096;

/// A stretch of a run read a buffer at a time, its bytes given back as they are read.
struct RunCursor<'a> {
    run: &'a Run<'a>,
    /// The records not yet read into the buffer.
    unread: Range<u64>,
    /// The byte up to which the stretch was given back.
    released: u64,
    buffer: Vec<u8>,
    /// Where the current record starts in the buffer.
    at: usize,
    capacity: u64,
}

impl<'a> RunCursor<'a> {
    fn new(run: &'a Run<'a>, records: Range<u64>, buffer_bytes: usize) -> Result<Self, StreamError> {
        let capacity = (buffer_bytes / run.record_bytes).max(1) as u64;
        let released = records.start * run.record_bytes as u64;
        let mut cursor = Self { run, unread: records, released, buffer: Vec::new(), at: 0, capacity };
        cursor.refill()?;
        Ok(cursor)
    }

    fn current(&self) -> Option<&[u8]> {
        self.buffer.get(self.at..self.at + self.run.record_bytes)
    }

    /// Moves to the next record and returns it; none past the stretch's end.
    fn advance(&mut self) -> Result<Option<&[u8]>, StreamError> {
        self.at += self.run.record_bytes;
        if self.at >= self.buffer.len() {
            self.refill()?;
        }
        Ok(self.current())
    }

    fn refill(&mut self) -> Result<(), StreamError> {
        let records = self.capacity.min(self.unread.end - self.unread.start);
        self.buffer.resize(records as usize * self.run.record_bytes, 0);
        self.run.read_at(&mut self.buffer, self.unread.start)?;
        self.unread.start += records;
        // Whole blocks as they are read, and the stretch's last bytes at its end: a block
        // shared with the next stretch is zeroed only in the part already read.
        let read_to = self.unread.start * self.run.record_bytes as u64;
        let release_to =
            if self.unread.is_empty() { read_to } else { read_to / RELEASE_ALIGN * RELEASE_ALIGN };
        if release_to > self.released {
            self.run.release(self.released..release_to);
            self.released = release_to;
        }
        self.at = 0;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::os::unix::fs::MetadataExt;

    use super::*;

    /// Bytes the file system holds for `path`.
    fn allocated(path: &Path) -> u64 {
        std::fs::metadata(path).unwrap().blocks() * 512
    }

    #[test]
    fn a_run_read_to_its_end_gives_its_room_back() {
        let dir = tempfile::tempdir().unwrap();
        let (path, record_bytes, records) = (dir.path().join("run-0"), 36, 100_000u64);
        let bytes: Vec<u8> = (0..record_bytes as u64 * records).map(|i| (i % 251) as u8).collect();
        std::fs::write(&path, &bytes).unwrap();
        let held = allocated(&path);
        assert!(held >= bytes.len() as u64, "{held} bytes held for {}", bytes.len());
        let run = Run::open(&path, record_bytes).unwrap();
        let mut cursor = RunCursor::new(&run, 0..records, 64 << 10).unwrap();
        let mut read = cursor.current().unwrap().to_vec();
        while let Some(record) = cursor.advance().unwrap() {
            read.extend_from_slice(record);
        }
        assert!(read == bytes, "every record read as written");
        let left = allocated(&path);
        assert!(left <= held / 100, "{left} of {held} bytes still held");
        assert_eq!(std::fs::metadata(&path).unwrap().len(), bytes.len() as u64, "the run keeps its length");
    }
}
