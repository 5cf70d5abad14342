//! Point sets larger than the GPU memory budget, streamed: split into tiles (runs of
//! patches in Morton order, so compact regions), each kept on the GPU with its records and
//! its own bottom level, in full or from its coarse level (`pointray_patches::coarse_level`:
//! about 6% of its patches). Every tile is drawn coarse where the budget holds that, and
//! those the camera needs most (`tile_view`) in full as far as the budget allows. As the
//! camera moves, tiles it no longer needs in full go back to coarse and the ones it now
//! needs are loaded in full, most needed first.

use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::{Affine3A, Vec3};
use pointray_kernels::Aabb;
use pointray_patches::PatchSet;
use pointray_patches::coarse_level::CoarseLevel;
use pointray_patches::patch_tiles::tile_ranges;
use pointray_scene::{Camera, Geometry, Scene};
use rayon::prelude::*;

use crate::acceleration::{AccelerationStructure, aabb_input, build_peak, build_sizes};
use crate::buffer::Buffer;
use crate::color_halo::{ColorHalo, NO_HALO};
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::ObjectRecord;
use crate::patch_upload::{
    check_patch_set, patch_records, range_record_bytes, reads_point_colors, tile_blas, tile_box_bytes,
};
use crate::prepared_scene::SceneLayout;
use crate::tile_view::TileView;
use pointray_scene::HotRecords;

/// Tiles a streamed set is split into, unless its tiles would be smaller than
/// `MIN_STREAMED_TILE` or larger than `MAX_STREAMED_TILE` (or the device's limit, or what
/// the budget holds: `prepared_scene::start_streaming`): enough that the budget can follow
/// the camera.
const TILES_PER_SET: usize = 64;

/// The fewest patches a streamed tile holds, below which a bottom level's fixed costs dominate.
pub(crate) const MIN_STREAMED_TILE: usize = 4096;

/// The most patches a streamed tile holds, so that loading one (about 17 ms for 1.56M patches
/// on an H100) keeps within a frame's share of time however large the set.
const MAX_STREAMED_TILE: usize = 1 << 21;

/// Where the tiles of a streamed scene stand after `TileStream::update`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TileResidency {
    /// Tiles of the streamed point sets.
    pub tiles: usize,
    /// Tiles on the GPU in full now, and tiles drawn from their coarse level.
    pub resident: usize,
    pub coarse: usize,
    /// Tiles the camera's view reaches, how many of them are on the GPU in full and how many
    /// coarse.
    pub in_view: usize,
    pub in_view_resident: usize,
    pub in_view_coarse: usize,
    /// Tiles this update loaded (in full or coarse, in place of the other level or not) and
    /// evicted (took off the GPU at every level); the first update after a streamed scene is
    /// prepared counts those its preparation loaded too.
    pub loaded: usize,
    pub evicted: usize,
    /// Tiles whose level fits the budget but was not loaded within the update's time limit.
    pub pending: usize,
    /// GPU bytes the resident tiles hold, and the most they may.
    pub resident_bytes: u64,
    pub budget_bytes: u64,
}

impl TileResidency {
    /// Whether this update, or for the first one the scene's preparation, changed what the
    /// scene shows.
    pub fn changed(&self) -> bool {
        self.loaded + self.evicted > 0
    }

    /// Tiles in or beside the view that are not on the GPU, in full or coarse.
    pub fn missing_in_view(&self) -> usize {
        self.in_view - self.in_view_resident - self.in_view_coarse
    }

    /// Tiles on the GPU neither in full nor coarse: only where the budget cannot hold every
    /// tile's coarse level.
    pub fn missing(&self) -> usize {
        self.tiles - self.resident - self.coarse
    }
}

/// Which of its levels a tile is drawn from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Level {
    Coarse,
    Full,
}

/// One streamed point set: its patches, its coarse level, where it stands and its record
/// (material, object).
struct StreamedSet {
    patches: Arc<PatchSet>,
    /// None where the layout draws no tile coarse.
    coarse: Option<Arc<CoarseLevel>>,
    transform: Affine3A,
    record: ObjectRecord,
}

/// One tile of a streamed set.
struct StreamedTile {
    set: usize,
    patches: Range<usize>,
    /// The coarse patches that stand for them (none without a coarse level).
    coarse: Range<usize>,
    /// Its patches' boxes, in world space.
    bounds: Aabb,
    /// GPU bytes it may take while loaded in full and coarse (0 without a coarse level): its
    /// records and its bottom level uncompacted. Not the compacted size seen once loaded, so that which tiles a
    /// camera gets does not depend on which were loaded before.
    bytes: u64,
    coarse_bytes: u64,
    /// The most its build holds at once, in full (a coarse one holds less): boxes,
    /// structure and scratch.
    build: u64,
    /// Where its set's hits are coloured by the points, the patches past its border that its
    /// colour blends read.
    colors: Option<ColorHalo>,
}

/// A tile on the GPU.
pub(crate) struct ResidentTile {
    pub(crate) blas: AccelerationStructure,
    pub(crate) buffers: Vec<Buffer>,
    pub(crate) record: ObjectRecord,
    pub(crate) transform: Affine3A,
    level: Level,
}

impl ResidentTile {
    fn bytes(&self) -> u64 {
        self.blas.size() + self.buffers.iter().map(|buffer| buffer.size).sum::<u64>()
    }
}

pub(crate) struct TileStream {
    sets: Vec<StreamedSet>,
    tiles: Vec<StreamedTile>,
    /// By tile index, so that the instances keep one order whatever the loading order.
    pub(crate) resident: BTreeMap<usize, ResidentTile>,
    layout: SceneLayout,
    /// What the tiles may hold at once: the budget less the scene's other holdings and the
    /// room one tile's build takes while it runs.
    budget: u64,
    /// The most the tiles held at once, a load's build included.
    pub(crate) peak: u64,
    /// Whether tiles were evicted or loaded since `take_changes` last looked.
    changed: bool,
}

impl TileStream {
    /// The form of the tiles' hot records.
    pub(crate) fn hot_records(&self) -> HotRecords {
        self.layout.hot_records
    }

    /// The tiles of `scene`'s point sets, none loaded yet, with at most `max_tile` patches
    /// each, and the room that building the largest of them takes beside them. `coarse`
    /// holds the coarse level of each point set, in the scene's order, where the layout
    /// draws tiles coarse; it is empty where it does not.
    pub(crate) fn new(
        context: &GpuContext,
        scene: &Scene,
        layout: SceneLayout,
        max_tile: u32,
        coarse: &[Arc<CoarseLevel>],
    ) -> Result<(Self, u64), VulkanError> {
        let mut stream = Self {
            sets: Vec::new(),
            tiles: Vec::new(),
            resident: BTreeMap::new(),
            layout,
            budget: 0,
            peak: 0,
            changed: false,
        };
        let mut largest_build = 0;
        for (index, object) in scene.objects.iter().enumerate() {
            let Geometry::Patches(patches) = &object.geometry else { continue };
            check_patch_set(patches)?;
            let set = stream.sets.len();
            let coarse = coarse.get(set);
            let most = patches
                .len()
                .div_ceil(TILES_PER_SET)
                .clamp(MIN_STREAMED_TILE, MAX_STREAMED_TILE)
                .min(max_tile as usize);
            for range in tile_ranges(patches.len(), most) {
                let (structure, scratch) = build_sizes(context, &aabb_input(0, range.len(), layout.blas));
                let build = build_peak(tile_box_bytes(&range, layout.blas), structure, scratch);
                largest_build = largest_build.max(build);
                let colors =
                    reads_point_colors(&object.material).then(|| ColorHalo::new(patches, range.clone()));
                let records = range_record_bytes(
                    patches,
                    range.clone(),
                    layout.buffers,
                    layout.hot_records,
                    colors.as_ref(),
                );
                let bounds = world_bounds(patches, range.clone(), &object.transform);
                let coarse_range = coarse.map_or(0..0, |coarse| coarse.covering(range.clone()));
                let coarse_colors = colors.as_ref().map(|_| &NO_HALO);
                let coarse_bytes = coarse.map_or(0, |coarse| {
                    level_bytes(context, &coarse.patches, coarse_range.clone(), layout, coarse_colors)
                });
                stream.tiles.push(StreamedTile {
                    set,
                    patches: range,
                    coarse: coarse_range,
                    bounds,
                    bytes: records + structure,
                    coarse_bytes,
                    build,
                    colors,
                });
            }
            let record = ObjectRecord::default().with_material(&object.material).for_tile(
                index as u32,
                0..0,
                layout.blas,
            );
            let (patches, coarse) = (patches.clone(), coarse.cloned());
            stream.sets.push(StreamedSet { patches, coarse, transform: object.transform, record });
        }
        Ok((stream, largest_build))
    }

    /// Tiles in all.
    pub(crate) fn len(&self) -> usize {
        self.tiles.len()
    }

    /// The patches of the largest tile.
    pub(crate) fn largest_tile_patches(&self) -> usize {
        self.tiles.iter().map(|tile| tile.patches.len()).max().unwrap_or(0)
    }

    /// The GPU bytes of the smallest tile loaded as the layout draws it at the least: coarse
    /// where it draws tiles coarse, else in full.
    pub(crate) fn smallest_tile_bytes(&self) -> u64 {
        let least =
            |tile: &StreamedTile| if self.layout.coarse_tiles { tile.coarse_bytes } else { tile.bytes };
        self.tiles.iter().map(least).min().unwrap_or(0)
    }

    /// Sets what the tiles may hold at once.
    pub(crate) fn set_budget(&mut self, bytes: u64) {
        self.budget = bytes;
    }

    /// Evicts the resident tiles `camera` (with an image `aspect` wide) no longer needs and
    /// loads the levels it needs in place of those on the GPU, the coarse ones first, then
    /// the full ones most needed first, until `limit` has passed (at least one each call, so
    /// that every call makes progress). Before anything changes it calls `idle`, which makes
    /// sure the GPU no longer reads what may go.
    pub(crate) fn update(
        &mut self,
        context: &Arc<GpuContext>,
        camera: &Camera,
        aspect: f32,
        limit: Option<Duration>,
        idle: impl FnOnce() -> Result<(), VulkanError>,
    ) -> Result<TileResidency, VulkanError> {
        let started = Instant::now();
        let view = TileView::new(camera, aspect);
        let bounds: Vec<Aabb> = self.tiles.iter().map(|tile| tile.bounds).collect();
        let seen: Vec<bool> = bounds.iter().map(|tile| view.sees(tile)).collect();
        let wanted = self.wanted(&view.rank(&bounds, &seen));
        let mut kept = vec![false; self.tiles.len()];
        wanted.iter().for_each(|&(tile, _)| kept[tile] = true);
        // A tile wanted at the other level stays until that replaces it, so that it never goes
        // missing while the loads take their calls; the coarse ones, which free room, come first.
        let evict: Vec<usize> = self.resident.keys().copied().filter(|&tile| !kept[tile]).collect();
        let missing: Vec<(usize, Level)> =
            wanted.iter().copied().filter(|&(tile, level)| self.level(tile) != Some(level)).collect();
        if !evict.is_empty() || !missing.is_empty() {
            idle()?;
        }
        for tile in &evict {
            self.resident.remove(tile);
            self.changed = true;
        }
        let mut loaded = 0;
        let mut held: u64 = self.resident.values().map(ResidentTile::bytes).sum();
        for (tile, level) in missing {
            if loaded > 0 && limit.is_some_and(|limit| started.elapsed() >= limit) {
                break;
            }
            if let Some(replaced) = self.resident.remove(&tile) {
                held -= replaced.bytes();
            }
            self.peak = self.peak.max(held + self.tiles[tile].build);
            let resident = self.load(context, tile, level)?;
            held += resident.bytes();
            self.peak = self.peak.max(held);
            self.resident.insert(tile, resident);
            self.changed = true;
            loaded += 1;
        }
        let pending = wanted.iter().filter(|&&(tile, level)| self.level(tile) != Some(level)).count();
        Ok(TileResidency {
            loaded,
            evicted: evict.len(),
            pending,
            resident_bytes: held,
            ..self.residency(&seen)
        })
    }

    /// How many tiles are on the GPU at each level, of all and of those `seen`.
    fn residency(&self, seen: &[bool]) -> TileResidency {
        let count = |level, in_view: bool| {
            let at_level = self.resident.iter().filter(|(_, resident)| resident.level == level);
            at_level.filter(|&(&tile, _)| !in_view || seen[tile]).count()
        };
        TileResidency {
            tiles: self.tiles.len(),
            resident: count(Level::Full, false),
            coarse: count(Level::Coarse, false),
            in_view: seen.iter().filter(|&&seen| seen).count(),
            in_view_resident: count(Level::Full, true),
            in_view_coarse: count(Level::Coarse, true),
            budget_bytes: self.budget,
            ..TileResidency::default()
        }
    }

    /// The level tile `tile` is on the GPU at, if it is.
    fn level(&self, tile: usize) -> Option<Level> {
        self.resident.get(&tile).map(|resident| resident.level)
    }

    /// Whether tiles were evicted or loaded since the last call: the top level must then be
    /// rebuilt, even where the update failed part way.
    pub(crate) fn take_changes(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    /// The tiles to hold and at which level, in the order to load them. With the layout's
    /// `coarse_tiles`, coarse, in `ranked` order, each whose coarse level fits beside those
    /// before it (every tile, unless the budget cannot hold their coarse levels); then, in
    /// `ranked` order, those of them whose full level still fits in place of their coarse
    /// one. Without, in full, in `ranked` order, each that fits beside those before it.
    fn wanted(&self, ranked: &[usize]) -> Vec<(usize, Level)> {
        let coarse_bytes = |tile: usize| self.tiles[tile].coarse_bytes;
        let mut held = 0;
        let mut drawn = Vec::new();
        for &tile in ranked {
            if held + coarse_bytes(tile) <= self.budget {
                held += coarse_bytes(tile);
                drawn.push(tile);
            }
        }
        let (mut full, mut in_full) = (Vec::new(), vec![false; self.tiles.len()]);
        for &tile in &drawn {
            let more = self.tiles[tile].bytes.saturating_sub(coarse_bytes(tile));
            if held + more <= self.budget {
                held += more;
                full.push((tile, Level::Full));
                in_full[tile] = true;
            }
        }
        let coarse = drawn.into_iter().filter(|&tile| self.layout.coarse_tiles && !in_full[tile]);
        coarse.map(|tile| (tile, Level::Coarse)).chain(full).collect()
    }

    /// Tile `index` at `level` onto the GPU: its bottom level and its records, whose
    /// addresses are offset so that the shaders index them by the patch's index in its set's
    /// patches or coarse level.
    fn load(
        &self,
        context: &Arc<GpuContext>,
        index: usize,
        level: Level,
    ) -> Result<ResidentTile, VulkanError> {
        let tile = &self.tiles[index];
        let set = &self.sets[tile.set];
        let (patches, range, colors) = match level {
            Level::Full => (&*set.patches, tile.patches.clone(), tile.colors.as_ref()),
            Level::Coarse => {
                let coarse = set.coarse.as_ref().ok_or_else(|| {
                    VulkanError::InvalidScene(
                        "a tile is drawn coarse, but its set has no coarse level".into(),
                    )
                })?;
                (&coarse.patches, tile.coarse.clone(), tile.colors.as_ref().map(|_| &NO_HALO))
            }
        };
        let blas = tile_blas(context, patches, range.clone(), self.layout.blas)?;
        let (addresses, buffers) = patch_records(
            context,
            patches,
            range.clone(),
            self.layout.buffers,
            self.layout.hot_records,
            colors,
        )?;
        let record = ObjectRecord {
            hot: addresses.hot,
            cold: addresses.cold,
            combined: addresses.combined,
            color_neighbors: addresses.color_neighbors,
            ..set.record.for_tile(set.record.object_index, range.clone(), self.layout.blas)
        };
        Ok(ResidentTile { blas, buffers, record, transform: set.transform, level })
    }
}

/// The GPU bytes `patches` in `range` take loaded: their records and their bottom level
/// uncompacted.
fn level_bytes(
    context: &GpuContext,
    patches: &PatchSet,
    range: Range<usize>,
    layout: SceneLayout,
    colors: Option<&ColorHalo>,
) -> u64 {
    let (structure, _) = build_sizes(context, &aabb_input(0, range.len(), layout.blas));
    range_record_bytes(patches, range, layout.buffers, layout.hot_records, colors) + structure
}

/// The world-space box of the patches in `range` of `patches`, placed by `transform`.
fn world_bounds(patches: &PatchSet, range: Range<usize>, transform: &Affine3A) -> Aabb {
    let local = patches.aabbs[range]
        .par_iter()
        .copied()
        .reduce_with(|a, b| a.union(&b))
        .unwrap_or(Aabb::new(Vec3::ZERO, Vec3::ZERO));
    let corner = |i: usize| {
        let pick = |axis: usize| if i >> axis & 1 == 0 { local.min[axis] } else { local.max[axis] };
        transform.transform_point3(Vec3::new(pick(0), pick(1), pick(2)))
    };
    let corners: Vec<Vec3> = (0..8).map(corner).collect();
    let min = corners.iter().copied().reduce(Vec3::min).expect("eight corners");
    let max = corners.iter().copied().reduce(Vec3::max).expect("eight corners");
    Aabb::new(min, max)
}
