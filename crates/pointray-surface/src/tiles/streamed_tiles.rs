//! Prep in tiles from a cloud read in chunks, in bounded memory: a first read finds the
//! bounds and the sample the centre is placed by (and so the recentring, the duplicate
//! distance and the Morton curve of the whole cloud, as a single pass has them), a second
//! sorts the points along the curve out of core, and each tile is then read back with the
//! halo of points its own reach, from whichever neighbouring tiles hold them. The tiles are
//! those of `tiles::tiled_prep`, and so are their patches, bit for bit.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{DVec3, Vec3};
use pointray_io::formats::copc_octree::CopcOctree;
use pointray_io::{MemoryBudget, PointCloud, PointStream};
use pointray_patches::PrepSettings;
use pointray_patches::patch_tiles::even_ranges;
use rayon::prelude::*;

use crate::duplicates::largest_merge_distance;
use crate::input_validation::validate_bounds;
use crate::morton::MortonGrid;
use crate::prep::{TileContext, prep_in_context};
use crate::prep_error::PrepError;
use crate::prep_progress::{NoProgress, PrepProgress, Stage};
use crate::tiles::cloud_subset::subset;
use crate::tiles::curve_span::CurveSpan;
use crate::tiles::halo_reach::{CURVE_CONTEXT, halo_reaches};
use crate::tiles::halo_test::HaloTest;
use crate::tiles::octree_sort::{OctreeSort, OctreeSortPlan, octree_grid, sort_along_octree};
use crate::tiles::out_of_core_sort::{SortPlan, sort_points};
use crate::tiles::point_records::KEYED_POSITION_BYTES;
use crate::tiles::sorted_points::SortedPoints;
use crate::tiles::stream_budget::{MIN_TILE_POINTS, STORE_BYTES_PER_POINT, StreamBudget};
use crate::tiles::stream_error::StreamError;
use crate::tiles::tiled_prep::{TilePatches, own_patches};
use crate::trimmed_centre::{CENTRE_SAMPLE_POINTS, CentreSample, trimmed_centre};

/// How many tiles to cut the cloud into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileCount {
    /// As few as the budget allows, and at least this many.
    AtLeast(usize),
    /// Exactly this many (tiles prepped as separate jobs must agree); refused when one
    /// would not fit the budget.
    Exactly(usize),
}

/// The box of a cloud's points (min, max), the offset it is recentred by, how many points
/// it holds and the curve they are sorted along: what a first read finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CloudBox {
    pub bounds: (DVec3, DVec3),
    pub offset: DVec3,
    pub points: u64,
    pub grid: MortonGrid,
}

impl CloudBox {
    /// A cloud sorted along the curve over its own box, as a single pass sorts it.
    pub(crate) fn over_its_box(bounds: (DVec3, DVec3), offset: DVec3, points: u64) -> Self {
        let grid = MortonGrid::over((bounds.0 - offset).as_vec3(), (bounds.1 - offset).as_vec3());
        Self { bounds, offset, points, grid }
    }
}

/// What a cloud's box and the settings give, checked: the tiles' shared context, the curve,
/// the number of tiles and the budget.
struct Cut {
    frame: TileContext,
    grid: MortonGrid,
    tiles: usize,
    budget: StreamBudget,
}

impl Cut {
    fn new(
        input: &Path,
        cloud: &CloudBox,
        settings: &PrepSettings,
        (count, memory, attribute_bytes): (TileCount, MemoryBudget, u64),
    ) -> Result<Self, StreamError> {
        let budget = StreamBudget::new(memory, attribute_bytes);
        let (points, (min, max)) = (cloud.points, cloud.bounds);
        let prep_error = |source| StreamError::Prep { path: input.to_path_buf(), source };
        let k = settings.k.max(settings.normal_k) as usize;
        if points <= k as u64 {
            return Err(prep_error(PrepError::TooFewPoints { found: points as usize, k }));
        }
        validate_bounds(min, max, points as usize).map_err(prep_error)?;
        if points > u64::from(u32::MAX) {
            let problem = format!("{points} points: prep numbers points with 32 bits, at most {}", u32::MAX);
            return Err(prep_error(PrepError::TooLarge { problem }));
        }
        let tiles = tile_count(count, points, settings, &budget, input)?;
        let budget = budget.with_store_writing(points);
        let offset = cloud.offset;
        let (low, high) = ((min - offset).as_vec3(), (max - offset).as_vec3());
        let frame = TileContext {
            offset,
            duplicate_distance: largest_merge_distance(
                low.abs().max(high.abs()).max_element(),
                settings.duplicate_tolerance,
            ),
            bounds: (min, max),
            points: points as usize,
        };
        Ok(Self { frame, grid: cloud.grid, tiles, budget })
    }

    /// The plan over `sorted`, the cloud of `input` sorted along this cut's curve.
    fn over(self, input: PathBuf, sorted: SortedPoints) -> StreamPlan {
        let Self { frame, grid, tiles, budget } = self;
        let tiles = even_ranges(sorted.len() as usize, tiles)
            .into_iter()
            .map(|range| range.start as u64..range.end as u64)
            .collect();
        StreamPlan { input, frame, grid, sorted, tiles, budget }
    }
}

/// A cloud sorted along its curve in scratch files, cut into tiles.
pub struct StreamPlan {
    input: PathBuf,
    pub frame: TileContext,
    /// The curve the points are sorted along.
    grid: MortonGrid,
    sorted: SortedPoints,
    tiles: Vec<Range<u64>>,
    budget: StreamBudget,
}

impl StreamPlan {
    /// Sorts `stream` into `scratch`: a COPC file along its octree in one read where that
    /// fits (`octree_sort`), any other in two reads.
    pub fn new(
        stream: &mut PointStream,
        settings: &PrepSettings,
        (count, memory): (TileCount, MemoryBudget),
        scratch: &Path,
        progress: &dyn PrepProgress,
    ) -> Result<Self, StreamError> {
        let input = stream.path().to_path_buf();
        let attribute_bytes = stream.attribute_bytes_per_point();
        if let Some(octree) = stream.copc_octree(CENTRE_SAMPLE_POINTS)? {
            let along =
                Self::along_octree(&octree, settings, (count, memory, attribute_bytes), scratch, progress)?;
            if let Some(plan) = along {
                return Ok(plan);
            }
        }
        let chunk_points = StreamBudget::new(memory, attribute_bytes).chunk_points();
        let (min, max, centre) = survey_bounds(stream, chunk_points, progress)?;
        let cloud = CloudBox::over_its_box((min, max), centre.centre(), stream.len());
        let cut = Cut::new(&input, &cloud, settings, (count, memory, attribute_bytes))?;
        let plan = SortPlan {
            grid: cut.grid,
            offset: cloud.offset,
            chunk_points: cut.budget.chunk_points(),
            run_bytes: cut.budget.run_bytes(),
            folder: scratch,
        };
        let sorted = sort_points(stream, &plan, progress)?;
        Ok(cut.over(input, sorted))
    }

    /// The plan over a COPC file sorted along its octree, or none when that sort is
    /// declined (logged with the reason) or the out-of-core sort will refuse the cloud.
    fn along_octree(
        octree: &CopcOctree,
        settings: &PrepSettings,
        (count, memory, attribute_bytes): (TileCount, MemoryBudget, u64),
        scratch: &Path,
        progress: &dyn PrepProgress,
    ) -> Result<Option<Self>, StreamError> {
        let input = octree.path().to_path_buf();
        let points = octree.points();
        let declined = |why: &str| {
            tracing::info!("{}: {why}; sorting it out of core instead", input.display());
            Ok(None)
        };
        // The out-of-core route says why it refuses these.
        if points <= u64::from(settings.k.max(settings.normal_k)) || points > u64::from(u32::MAX) {
            return Ok(None);
        }
        let budget = StreamBudget::new(memory, attribute_bytes);
        tile_count(count, points, settings, &budget, &input)?;
        let budget = budget.with_store_writing(points);
        let offset = trimmed_centre(octree.sample());
        let Some(grid) = octree_grid(octree, offset) else {
            return declined("its octree's cube has no finite size");
        };
        let plan = OctreeSortPlan {
            grid,
            offset,
            batch_points: budget.octree_batch_points(),
            waiting_bytes: budget.run_bytes() as u64,
            record_bytes: KEYED_POSITION_BYTES + attribute_bytes,
            folder: scratch,
        };
        match sort_along_octree(octree, &plan, progress)? {
            OctreeSort::Sorted { bounds, sorted } => {
                let cloud = CloudBox { bounds, offset, points, grid };
                let cut = Cut::new(&input, &cloud, settings, (count, memory, attribute_bytes))?;
                Ok(Some(cut.over(input, sorted)))
            }
            OctreeSort::Declined(why) => declined(&why),
        }
    }

    /// The plan over a cloud sorted once and kept (`tiles::kept_sort`), read from `folder`.
    pub(crate) fn of_kept(
        folder: &Path,
        (cloud, sorted): (CloudBox, SortedPoints),
        settings: &PrepSettings,
        (count, memory): (TileCount, MemoryBudget),
    ) -> Result<Self, StreamError> {
        let attribute_bytes = sorted.layout().attribute_bytes();
        let cut = Cut::new(folder, &cloud, settings, (count, memory, attribute_bytes))?;
        Ok(cut.over(folder.to_path_buf(), sorted))
    }

    /// The box, recentring and point count of the whole cloud.
    pub(crate) fn cloud_box(&self) -> CloudBox {
        CloudBox {
            bounds: self.frame.bounds,
            offset: self.frame.offset,
            points: self.frame.points as u64,
            grid: self.grid,
        }
    }

    /// The sorted points, for keeping.
    pub(crate) fn into_sorted(self) -> SortedPoints {
        self.sorted
    }

    pub fn tile_count(&self) -> usize {
        self.tiles.len()
    }

    /// The points of the whole cloud.
    pub fn points(&self) -> u64 {
        self.sorted.len()
    }

    /// The points tile `index` owns.
    pub fn tile_points(&self, index: usize) -> u64 {
        self.tiles.get(index).map_or(0, |range| range.end - range.start)
    }

    /// The points of each tile, in order along the curve (positions in the sorted cloud).
    pub fn tile_ranges(&self) -> &[Range<u64>] {
        &self.tiles
    }

    /// Preps tile `index` with its halo; its patches name their points (and colour
    /// neighbours) by input index, as `tiles::tiled_prep::prep_tile`'s do.
    pub fn prep_tile(&self, settings: &PrepSettings, index: usize) -> Result<TilePatches, StreamError> {
        let range = self.tiles.get(index).cloned().ok_or_else(|| StreamError::Prep {
            path: self.input.clone(),
            source: PrepError::NoSuchTile { index, count: self.tile_count() },
        })?;
        match self.gather_range(settings, range)? {
            Gathered::Tile(tile) => self.prep_gathered(settings, *tile),
            Gathered::OverBudget { points } => {
                Err(self.over_budget(&format!("tile {index}"), points, settings))
            }
        }
    }

    /// The points at sorted positions `range` with their halo, in the order a tile takes
    /// them, unless they would not fit the budget.
    pub(crate) fn gather_range(
        &self,
        settings: &PrepSettings,
        range: Range<u64>,
    ) -> Result<Gathered, StreamError> {
        let started = Instant::now();
        let (core, core_inputs) = self.sorted.read_range(range.clone())?;
        let offset = self.frame.offset;
        let local = |cloud: &PointCloud| -> Vec<Vec3> {
            cloud.positions.par_iter().map(|&p| (p - offset).as_vec3()).collect()
        };
        let (before, _) =
            self.sorted.read_range(range.start.saturating_sub(CURVE_CONTEXT as u64)..range.start)?;
        let (after, _) =
            self.sorted.read_range(range.end..(range.end + CURVE_CONTEXT as u64).min(self.sorted.len()))?;
        let curve: Vec<Vec3> = [local(&before), local(&core), local(&after)].concat();
        let core_in_curve = before.len()..before.len() + core.len();
        let read = started.elapsed();
        let span =
            CurveSpan::new(self.grid, self.sorted.code_at(range.start)?, self.sorted.code_at(range.end - 1)?);
        let reaches = halo_reaches(
            &curve,
            core_in_curve.clone(),
            settings,
            (self.frame.duplicate_distance, Some(&span)),
        );
        let reached = started.elapsed();
        let core_points = &curve[core_in_curve];
        let capacity = self.budget.tile_capacity(settings);
        let core_count = core.len() as u64;
        let halo_test = HaloTest::new(core_points, &reaches);
        let (halo_records, halo_count) =
            self.gather(&halo_test, &range, capacity.saturating_sub(core_count))?;
        if core_count + halo_count > capacity {
            return Ok(Gathered::OverBudget { points: core_count + halo_count });
        }
        let gathered = started.elapsed();
        let (halo, halo_inputs) = self.sorted.decode_records(&halo_records);
        drop(halo_records);
        // The halo in input order, as the in-memory tiles take it.
        let mut by_input: Vec<u32> = (0..halo_inputs.len() as u32).collect();
        by_input.par_sort_unstable_by_key(|&j| halo_inputs[j as usize]);
        let core_len = core.len();
        let members: Vec<u32> =
            core_inputs.iter().copied().chain(by_input.iter().map(|&j| halo_inputs[j as usize])).collect();
        let mut cloud = core;
        cloud.append(subset(&halo, &by_input));
        tracing::debug!(
            "tile {range:?} gathered: {halo_count} halo points; read {read:.2?}, reach {:.2?}, \
             halo {:.2?}, assemble {:.2?}",
            reached - read,
            gathered - reached,
            started.elapsed() - gathered
        );
        Ok(Gathered::Tile(Box::new(GatheredTile { range, cloud, members, core: core_len })))
    }

    /// Preps a gathered tile.
    pub(crate) fn prep_gathered(
        &self,
        settings: &PrepSettings,
        tile: GatheredTile,
    ) -> Result<TilePatches, StreamError> {
        let started = Instant::now();
        let GatheredTile { range, cloud, members, core } = tile;
        let (patches, report) =
            prep_in_context(&cloud, settings, &self.frame, &NoProgress).map_err(|source| {
                StreamError::Prep { path: self.input.clone(), source: source.of_tile(&members) }
            })?;
        let stages: Vec<String> =
            report.stage_times.iter().map(|(stage, time)| format!("{} {time:.2?}", stage.name())).collect();
        tracing::debug!("tile {range:?} prepped in {:.2?}: {}", started.elapsed(), stages.join(", "));
        Ok(own_patches(patches, &report.patch_sources, &members, core))
    }

    /// The records of the points outside `core` (sorted positions) that `test` reaches, and
    /// how many there are; past `room` points only the count goes on.
    fn gather(&self, test: &HaloTest, core: &Range<u64>, room: u64) -> Result<(Vec<u8>, u64), StreamError> {
        let (mut kept, mut count, size) = (Vec::new(), 0u64, self.sorted.record_bytes());
        self.sorted.near(test, core, self.budget.halo_batch_points(), |points, records| {
            let record = |j: u32| &records[j as usize * size..(j as usize + 1) * size];
            for j in test.reached(points) {
                count += 1;
                if count <= room {
                    kept.extend_from_slice(record(j));
                }
            }
        })?;
        Ok((kept, count))
    }

    /// Why `tile`, holding `points` with its halo, cannot be prepped.
    pub fn over_budget(&self, tile: &str, points: u64, settings: &PrepSettings) -> StreamError {
        let problem = format!(
            "{tile} with its halo holds {points} points, but the memory budget holds about {}: \
             raise the memory budget or cut the cloud into more tiles",
            self.budget.tile_capacity(settings)
        );
        StreamError::OverBudget { path: self.input.clone(), problem }
    }
}

/// A tile's points with their halo, ready for prep, or how many there are when they do not
/// fit.
pub(crate) enum Gathered {
    Tile(Box<GatheredTile>),
    OverBudget { points: u64 },
}

pub(crate) struct GatheredTile {
    /// The tile's points, as sorted positions.
    pub range: Range<u64>,
    /// Its own points, then its halo's.
    cloud: PointCloud,
    /// Each point's input index.
    members: Vec<u32>,
    /// How many of the points are its own.
    core: usize,
}

/// The bounds of the cloud and the sample that places its centre, from a first read;
/// non-finite coordinates are refused.
fn survey_bounds(
    stream: &mut PointStream,
    chunk: usize,
    progress: &dyn PrepProgress,
) -> Result<(DVec3, DVec3, CentreSample), StreamError> {
    let input = stream.path().to_path_buf();
    progress.stage_started(Stage::Survey, stream.len());
    let started = std::time::Instant::now();
    let (mut min, mut max, mut seen) = (DVec3::INFINITY, DVec3::NEG_INFINITY, 0usize);
    let mut centre = CentreSample::new(stream.len());
    stream.survey(chunk, |positions| {
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            let source = PrepError::NonFiniteCoordinate { index: seen + i };
            return Err(StreamError::Prep { path: input.clone(), source });
        }
        for &p in positions {
            (min, max) = (min.min(p), max.max(p));
        }
        centre.offer(seen as u64, positions);
        seen += positions.len();
        progress.advanced(positions.len() as u64);
        Ok(())
    })?;
    progress.stage_finished(Stage::Survey, started.elapsed());
    Ok((min, max, centre))
}

/// The tiles to cut `points` into within the budget.
fn tile_count(
    count: TileCount,
    points: u64,
    settings: &PrepSettings,
    budget: &StreamBudget,
    input: &Path,
) -> Result<usize, StreamError> {
    let over = |problem: String| StreamError::OverBudget { path: input.to_path_buf(), problem };
    if !budget.holds_store_writing(points) {
        return Err(over(format!(
            "{points} points: writing the store maps each to its patch and holds the coarse level \
             ({STORE_BYTES_PER_POINT} bytes a point), which the memory budget ({} MiB for the work) \
             cannot hold",
            budget.usable() >> 20
        )));
    }
    let budget = budget.with_store_writing(points);
    let core = budget.core_capacity(settings);
    if core < MIN_TILE_POINTS {
        return Err(over(format!(
            "the memory budget ({} MiB for the work) cannot hold one tile of {MIN_TILE_POINTS} points \
             with its halo: give it at least {} MiB",
            budget.usable() >> 20,
            budget.memory_for_smallest_tile(settings, points).div_ceil(1 << 20)
        )));
    }
    let needed = points.div_ceil(core) as usize;
    let (TileCount::AtLeast(wanted) | TileCount::Exactly(wanted)) = count;
    if wanted as u64 > points {
        return Err(StreamError::Prep {
            path: input.to_path_buf(),
            source: PrepError::TooManyTiles { tiles: wanted, points },
        });
    }
    match count {
        TileCount::AtLeast(wanted) => Ok(wanted.max(needed).max(1)),
        TileCount::Exactly(wanted) if wanted >= needed => Ok(wanted.max(1)),
        TileCount::Exactly(wanted) => Err(over(format!(
            "{wanted} tiles of about {} points do not fit the memory budget, which holds tiles of \
             about {core} with their halos: cut the cloud into at least {needed} tiles",
            points.div_ceil(wanted.max(1) as u64)
        ))),
    }
}
