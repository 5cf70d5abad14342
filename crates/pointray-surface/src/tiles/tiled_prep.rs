//! Prep in tiles: the cloud is sorted along one Morton curve over its whole bounding box and
//! cut into tiles of equal point counts; each tile is prepped with a halo of the points
//! around it, recentred and deduplicated as the whole cloud is (`TileContext`), and keeps the
//! patches of its own points. A tile needs only its points and its halo, so tiles can run
//! one after another in bounded memory or as separate jobs, and the merged patches are the
//! ones a single pass makes wherever a patch depends only on its neighbourhood: positions,
//! normals oriented toward a sensor or taken from the input, supports, fits and colours.
//! Normals oriented over the neighbour graph are settled within each tile and its halo, so
//! a whole tile's sign may differ from a single pass's (rendering shades both sides alike).

use std::ops::Range;

use glam::Vec3;
use pointray_io::PointCloud;
use pointray_kernels::NO_NEIGHBOR;
use pointray_patches::patch_tiles::even_ranges;
use pointray_patches::{PatchSet, PrepSettings};
use rayon::prelude::*;

use crate::input_validation::validate_positions;
use crate::morton::{MortonGrid, curve_and_order};
use crate::prep::{TileContext, bounds_of, gather, largest_duplicate_distance, prep_in_context, recentre_on};
use crate::prep_error::PrepError;
use crate::prep_progress::PrepProgress;
use crate::tiles::cloud_subset::subset;
use crate::tiles::curve_span::CurveSpan;
use crate::tiles::halo_reach::{CURVE_CONTEXT, halo_reaches};
use crate::tiles::halo_test::HaloTest;
use crate::tiles::patch_map::PatchMap;
use crate::trimmed_centre::trimmed_centre;

/// How a cloud is cut into tiles; the same input and count always give the same plan, so
/// separate jobs agree on it.
pub struct TilePlan {
    pub frame: TileContext,
    /// The Morton curve of the whole cloud (none when no point is finite).
    grid: Option<MortonGrid>,
    /// Input indices along that curve.
    order: Vec<u32>,
    tiles: Vec<Range<usize>>,
}

/// One tile's patches, with the input index of each one's point; its colour neighbours
/// name input indices too, until `merge_tiles` turns them into patch indices.
#[derive(Clone, Debug, PartialEq)]
pub struct TilePatches {
    pub patches: PatchSet,
    pub sources: Vec<u32>,
}

impl TilePlan {
    /// `tiles` tiles (at least 1) of `cloud` prepped with `settings`.
    pub fn new(cloud: &PointCloud, settings: &PrepSettings, tiles: usize) -> Self {
        let bounds = bounds_of(&cloud.positions);
        let offset = trimmed_centre(&cloud.positions);
        let recentred = recentre_on(&cloud.positions, offset);
        let frame = TileContext {
            offset,
            duplicate_distance: largest_duplicate_distance(settings, &recentred),
            bounds,
            points: cloud.len(),
        };
        let (grid, order) = curve_and_order(&recentred);
        let tiles = even_ranges(order.len(), tiles.max(1));
        Self { frame, grid, order, tiles }
    }

    pub fn tile_count(&self) -> usize {
        self.tiles.len()
    }

    /// The input indices of tile `index`'s own points.
    pub fn core(&self, index: usize) -> &[u32] {
        &self.order[self.tiles[index].clone()]
    }
}

/// Preps tile `index` of `plan` (an error past the last tile).
pub fn prep_tile(
    cloud: &PointCloud,
    settings: &PrepSettings,
    plan: &TilePlan,
    index: usize,
    progress: &dyn PrepProgress,
) -> Result<TilePatches, PrepError> {
    if index >= plan.tile_count() {
        return Err(PrepError::NoSuchTile { index, count: plan.tile_count() });
    }
    let core = plan.core(index);
    let local = |i: u32| (cloud.positions[i as usize] - plan.frame.offset).as_vec3();
    let range = &plan.tiles[index];
    let context =
        range.start.saturating_sub(CURVE_CONTEXT)..(range.end + CURVE_CONTEXT).min(plan.order.len());
    let curve: Vec<Vec3> = plan.order[context.clone()].par_iter().map(|&i| local(i)).collect();
    let core_in_curve = range.start - context.start..range.end - context.start;
    let ends = core.first().zip(core.last());
    let span = plan
        .grid
        .zip(ends)
        .map(|(grid, (&first, &last))| CurveSpan::new(grid, grid.code(local(first)), grid.code(local(last))));
    let reaches =
        halo_reaches(&curve, core_in_curve.clone(), settings, (plan.frame.duplicate_distance, span.as_ref()));
    let core_points = &curve[core_in_curve];
    let halo = halo_of(cloud.len(), core, core_points, &reaches, local);
    let members: Vec<u32> = core.iter().chain(&halo).copied().collect();
    let (patches, report) = prep_in_context(&subset(cloud, &members), settings, &plan.frame, progress)
        .map_err(|error| error.of_tile(&members))?;
    Ok(own_patches(patches, &report.patch_sources, &members, core.len()))
}

/// The points outside `core` within its point `i`'s `reaches[i]` of it, for any `i`, in
/// input order.
fn halo_of(
    count: usize,
    core: &[u32],
    core_points: &[Vec3],
    reaches: &[f32],
    local: impl Fn(u32) -> Vec3 + Sync,
) -> Vec<u32> {
    let halo = HaloTest::new(core_points, reaches);
    let mut in_core = vec![false; count];
    core.iter().for_each(|&i| in_core[i as usize] = true);
    let candidates: Vec<u32> = (0..count as u32)
        .into_par_iter()
        .filter(|&i| !in_core[i as usize] && halo.may_reach(local(i)))
        .collect();
    drop(in_core);
    let points: Vec<Vec3> = candidates.iter().map(|&i| local(i)).collect();
    halo.reached(&points).into_iter().map(|j| candidates[j as usize]).collect()
}

/// The patches of the tile's own points (the first `core` members), their colour neighbours
/// as input indices.
pub(crate) fn own_patches(set: PatchSet, sources: &[u32], members: &[u32], core: usize) -> TilePatches {
    let input_of = |patch: u32| members[sources[patch as usize] as usize];
    let keep: Vec<u32> =
        (0..set.len() as u32).into_par_iter().filter(|&j| (sources[j as usize] as usize) < core).collect();
    let width = if set.is_empty() { 0 } else { set.color_neighbors.len() / set.len() };
    let color_neighbors: Vec<u32> = keep
        .par_iter()
        .flat_map_iter(|&j| set.color_neighbors[j as usize * width..(j as usize + 1) * width].iter())
        .map(|&n| if n == NO_NEIGHBOR { NO_NEIGHBOR } else { input_of(n) })
        .collect();
    TilePatches {
        sources: keep.par_iter().map(|&j| input_of(j)).collect(),
        patches: PatchSet {
            settings: set.settings,
            offset: set.offset,
            aabbs: gather(&set.aabbs, &keep).into(),
            hot: gather(&set.hot, &keep).into(),
            cold: gather(&set.cold, &keep).into(),
            color_neighbors: color_neighbors.into(),
            coarse: None,
        },
    }
}

/// The tiles' patches as one set, in tile order; colour neighbours whose point made no
/// patch (merged away as a duplicate) become unused slots.
pub fn merge_tiles(tiles: Vec<TilePatches>) -> PatchSet {
    let inputs =
        tiles.iter().flat_map(|tile| tile.sources.iter()).map(|&i| i as usize + 1).max().unwrap_or(0);
    let mut patch_of = PatchMap::new(inputs);
    let mut first = 0;
    for tile in &tiles {
        patch_of.note(&tile.sources, first);
        first += tile.sources.len() as u64;
    }
    let mut merged = PatchSet::default();
    for tile in tiles {
        let set = tile.patches;
        merged.settings = set.settings;
        merged.offset = set.offset;
        merged.aabbs.to_mut().extend_from_slice(&set.aabbs);
        merged.hot.to_mut().extend_from_slice(&set.hot);
        merged.cold.to_mut().extend_from_slice(&set.cold);
        merged
            .color_neighbors
            .to_mut()
            .extend(set.color_neighbors.iter().map(|&input| patch_of.patch(input)));
    }
    merged
}

/// Every tile of `cloud` in turn, merged: at its peak the cloud and one tile's prep. More
/// tiles than points are refused, since a tile needs points of its own.
pub fn prep_tiled(
    cloud: &PointCloud,
    settings: &PrepSettings,
    tiles: usize,
    progress: &dyn PrepProgress,
) -> Result<PatchSet, PrepError> {
    validate_positions(&cloud.positions, settings.k as usize)?;
    if tiles > cloud.len() {
        return Err(PrepError::TooManyTiles { tiles, points: cloud.len() as u64 });
    }
    let plan = TilePlan::new(cloud, settings, tiles);
    let prepped = (0..plan.tile_count())
        .map(|index| prep_tile(cloud, settings, &plan, index, progress))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(merge_tiles(prepped))
}
