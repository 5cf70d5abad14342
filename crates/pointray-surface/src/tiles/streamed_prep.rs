//! Prep in bounded memory, from a cloud read in chunks: sorted out of core and prepped tile
//! by tile (`tiles::streamed_tiles`) in a scratch folder made in the folder the caller names
//! (the output's, unless the disk there cannot hold the sorted points), which is removed when
//! done or interrupted. One process preps every tile and merges them; or a job preps one
//! tile of a cut into a tile file, and a merge of all the tile files writes the same store.

use std::collections::VecDeque;
use std::ops::Range;
use std::path::Path;

use pointray_io::formats::ColumnSpec;
use pointray_io::temporaries::TemporaryFolder;
use pointray_io::{MemoryBudget, PointStream};
use pointray_patches::PrepSettings;

use crate::prep_progress::{PrepProgress, Stage};
use crate::tiles::disk_room::{ensure_room, sorted_points_need, store_need};
use crate::tiles::kept_sort::{is_kept_sort, open_kept};
use crate::tiles::merge::MergeSummary;
use crate::tiles::spool::TileSpool;
use crate::tiles::stream_budget::MIN_TILE_POINTS;
use crate::tiles::stream_error::StreamError;
use crate::tiles::streamed_tiles::{Gathered, StreamPlan, TileCount};
use crate::tiles::tile_file::write_tile_file;
use crate::tiles::tiled_prep::TilePatches;

/// Preps the whole of `stream` within `memory` and writes the store `output`, sorting the
/// points in a scratch folder made in `scratch_parent`. A tile whose halo would not fit is
/// split in two (jobs of a fixed cut refuse instead).
pub fn prep_streamed(
    stream: &mut PointStream,
    settings: &PrepSettings,
    (count, memory): (TileCount, MemoryBudget),
    (output, scratch_parent): (&Path, &Path),
    progress: &dyn PrepProgress,
) -> Result<MergeSummary, StreamError> {
    let store_folder = pointray_io::folder_of(output);
    ensure_room(&[sorted_points_need(stream, scratch_parent), store_need(stream.len(), store_folder)])?;
    let scratch = TemporaryFolder::new_in(scratch_parent)?;
    let plan = StreamPlan::new(stream, settings, (count, memory), scratch.path(), progress)?;
    prep_planned(&plan, settings, output, progress)
}

/// Preps the whole cloud whose sort `tiles::kept_sort` kept in `folder`, within `memory`,
/// and writes the store `output`: the store `prep_streamed` writes from the cloud itself,
/// without reading and sorting it again (as when prepping it once more with other settings).
pub fn prep_kept_streamed(
    folder: &Path,
    settings: &PrepSettings,
    (count, memory): (TileCount, MemoryBudget),
    output: &Path,
    progress: &dyn PrepProgress,
) -> Result<MergeSummary, StreamError> {
    let plan = open_kept(folder, settings, (count, memory))?;
    ensure_room(&[store_need(plan.points(), pointray_io::folder_of(output))])?;
    prep_planned(&plan, settings, output, progress)
}

/// Preps every tile of `plan` and writes the store `output`.
fn prep_planned(
    plan: &StreamPlan,
    settings: &PrepSettings,
    output: &Path,
    progress: &dyn PrepProgress,
) -> Result<MergeSummary, StreamError> {
    progress.stage_started(Stage::PrepTiles, plan.points());
    let started = std::time::Instant::now();
    let mut spool = TileSpool::new(output, plan.points(), (*settings, plan.frame.offset))?;
    let mut pending: VecDeque<Range<u64>> = plan.tile_ranges().iter().cloned().collect();
    let gather = |range: Range<u64>| plan.gather_range(settings, range.clone()).map(|g| (range, g));
    let mut next = pending.pop_front().map(gather).transpose()?;
    // The patches of the last tile prepped, written to the store while the next is prepped.
    let mut written: Option<TilePatches> = None;
    while let Some((range, gathered)) = next.take() {
        match gathered {
            // Prepping one tile, gathering the next and writing the one before overlap.
            Gathered::Tile(tile) => {
                let ((prepped, wrote), following) = beside(
                    || plan.prep_gathered(settings, *tile),
                    || written.take().map_or(Ok(()), |tile| spool.push(&tile)),
                    || pending.pop_front().map(gather).transpose(),
                );
                wrote?;
                written = Some(prepped?);
                progress.advanced(range.end - range.start);
                next = following?;
            }
            // A tile whose halo outgrew the budget is split in two along the curve.
            Gathered::OverBudget { .. } if range.end - range.start >= 2 * MIN_TILE_POINTS => {
                let middle = range.start + (range.end - range.start) / 2;
                pending.push_front(middle..range.end);
                next = Some(gather(range.start..middle)?);
            }
            Gathered::OverBudget { points } => {
                return Err(plan.over_budget(&format!("the tile of points {range:?}"), points, settings));
            }
        }
    }
    if let Some(tile) = written {
        spool.push(&tile)?;
    }
    progress.stage_finished(Stage::PrepTiles, started.elapsed());
    spool.write_store(progress)
}

/// `main` here, with `write` and `gather` beside it. From outside a thread pool the two run
/// on threads of their own: 100M points prepped in 47.4 and 54.1 s so, against 52.4 and 57.8 s
/// with the three joined in the pool (16 cores). A pool's own thread must not wait on work
/// that only the pool can run, so there the three are joined in the pool.
fn beside<M: Send, W: Send, G: Send>(
    main: impl FnOnce() -> M + Send,
    write: impl FnOnce() -> W + Send,
    gather: impl FnOnce() -> G + Send,
) -> ((M, W), G) {
    if rayon::current_thread_index().is_some() {
        return rayon::join(|| rayon::join(main, write), gather);
    }
    std::thread::scope(|scope| {
        let (write, gather) = (scope.spawn(write), scope.spawn(gather));
        let done = main();
        ((done, joined(write)), joined(gather))
    })
}

/// What a scoped thread returned; its panic goes on.
fn joined<T>(thread: std::thread::ScopedJoinHandle<'_, T>) -> T {
    thread.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
}

/// Preps tile `index` of `count` of the points at `points`, a cloud file (read with
/// `columns`) or a sort kept in that folder for tile jobs (`kept_sort`): what a tile job runs,
/// `prep --tile I --of N` or Python's `prep_tile`. Returns the tile's own points.
pub fn prep_tile_job(
    points: &Path,
    columns: Option<&ColumnSpec>,
    settings: &PrepSettings,
    cut: (usize, usize),
    memory: MemoryBudget,
    (output, scratch_parent): (&Path, &Path),
    progress: &dyn PrepProgress,
) -> Result<u64, StreamError> {
    if is_kept_sort(points) {
        return prep_one_kept_tile(points, settings, cut, memory, output, progress);
    }
    let mut stream = PointStream::open(points, columns, memory)?;
    prep_one_tile(&mut stream, settings, cut, memory, (output, scratch_parent), progress)
}

/// Preps tile `index` of `count` of `stream` within `memory` and writes it alone to the
/// tile file `output`, sorting the points in a scratch folder made in `scratch_parent`;
/// returns the points the tile owns.
pub fn prep_one_tile(
    stream: &mut PointStream,
    settings: &PrepSettings,
    (index, count): (usize, usize),
    memory: MemoryBudget,
    (output, scratch_parent): (&Path, &Path),
    progress: &dyn PrepProgress,
) -> Result<u64, StreamError> {
    ensure_room(&[sorted_points_need(stream, scratch_parent)])?;
    let scratch = TemporaryFolder::new_in(scratch_parent)?;
    let plan =
        StreamPlan::new(stream, settings, (TileCount::Exactly(count), memory), scratch.path(), progress)?;
    prep_planned_tile(&plan, settings, (index, count), output, progress)
}

/// Preps tile `index` of `count` of the cloud whose sort `tiles::kept_sort` kept in
/// `folder`, within `memory`, and writes it alone to the tile file `output`: the tile file
/// `prep_one_tile` writes from the cloud itself, without reading and sorting the whole cloud.
pub fn prep_one_kept_tile(
    folder: &Path,
    settings: &PrepSettings,
    (index, count): (usize, usize),
    memory: MemoryBudget,
    output: &Path,
    progress: &dyn PrepProgress,
) -> Result<u64, StreamError> {
    let plan = open_kept(folder, settings, (TileCount::Exactly(count), memory))?;
    prep_planned_tile(&plan, settings, (index, count), output, progress)
}

fn prep_planned_tile(
    plan: &StreamPlan,
    settings: &PrepSettings,
    (index, count): (usize, usize),
    output: &Path,
    progress: &dyn PrepProgress,
) -> Result<u64, StreamError> {
    progress.stage_started(Stage::PrepTiles, plan.tile_points(index));
    let started = std::time::Instant::now();
    let tile = plan.prep_tile(settings, index)?;
    write_tile_file(output, tile, (index, count), plan.points())?;
    progress.stage_finished(Stage::PrepTiles, started.elapsed());
    Ok(plan.tile_points(index))
}
