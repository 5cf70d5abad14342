//! Point sets larger than the GPU memory budget, streamed: split into tiles (runs of
//! patches in Morton order, so compact regions), of which those the camera needs are kept
//! on the GPU, each with its records and its own bottom level, as far as the budget allows.
//! As the camera moves, tiles it no longer needs are evicted and the ones it now needs are
//! loaded, most needed first (`tile_view`).

use std::collections::BTreeMap;
use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::{Affine3A, Vec3};
use pointray_kernels::Aabb;
use pointray_patches::PatchSet;
use pointray_patches::patch_tiles::tile_ranges;
use pointray_scene::{Camera, Geometry, Scene};
use rayon::prelude::*;

use crate::acceleration::{AccelerationStructure, aabb_input, build_peak, build_sizes};
use crate::buffer::Buffer;
use crate::color_halo::ColorHalo;
use crate::context::GpuContext;
use crate::error::VulkanError;
use crate::gpu_records::ObjectRecord;
use crate::patch_upload::{
    check_patch_set, patch_records, range_record_bytes, reads_point_colors, tile_blas, tile_box_bytes,
};
use crate::prepared_scene::SceneLayout;
use crate::tile_view::TileView;

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
    /// Tiles on the GPU now.
    pub resident: usize,
    /// Tiles the camera's view reaches, and how many of them are on the GPU.
    pub in_view: usize,
    pub in_view_resident: usize,
    /// Tiles this update loaded and evicted; the first update after a streamed scene is
    /// prepared counts those its preparation loaded too.
    pub loaded: usize,
    pub evicted: usize,
    /// Tiles that fit the budget but were not loaded within the update's time limit.
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

    /// Tiles in or beside the view that are not on the GPU.
    pub fn missing_in_view(&self) -> usize {
        self.in_view - self.in_view_resident
    }
}

/// One streamed point set: its patches, where it stands and its record (material, object).
struct StreamedSet {
    patches: Arc<PatchSet>,
    transform: Affine3A,
    record: ObjectRecord,
}

/// One tile of a streamed set.
struct StreamedTile {
    set: usize,
    patches: Range<usize>,
    /// Its patches' boxes, in world space.
    bounds: Aabb,
    /// GPU bytes it may take while loaded: its records and its bottom level uncompacted. Not
    /// the compacted size seen once loaded, so that which tiles a camera gets does not
    /// depend on which were loaded before.
    bytes: u64,
    /// The most its build holds at once: boxes, structure and scratch.
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
    /// The tiles of `scene`'s point sets, none loaded yet, with at most `max_tile` patches
    /// each, and the room that building the largest of them takes beside them.
    pub(crate) fn new(
        context: &GpuContext,
        scene: &Scene,
        layout: SceneLayout,
        max_tile: u32,
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
            let most = patches
                .len()
                .div_ceil(TILES_PER_SET)
                .clamp(MIN_STREAMED_TILE, MAX_STREAMED_TILE)
                .min(max_tile as usize);
            for range in tile_ranges(patches.len(), most) {
                let (structure, scratch) =
                    build_sizes(context, &aabb_input(0, range.len() as u32, layout.blas));
                let build = build_peak(tile_box_bytes(&range), structure, scratch);
                largest_build = largest_build.max(build);
                let colors =
                    reads_point_colors(&object.material).then(|| ColorHalo::new(patches, range.clone()));
                let records = range_record_bytes(patches, range.clone(), layout.buffers, colors.as_ref());
                let bounds = world_bounds(patches, range.clone(), &object.transform);
                stream.tiles.push(StreamedTile {
                    set,
                    patches: range,
                    bounds,
                    bytes: records + structure,
                    build,
                    colors,
                });
            }
            let record = ObjectRecord::default().with_material(&object.material).for_tile(index as u32, 0);
            stream.sets.push(StreamedSet { patches: patches.clone(), transform: object.transform, record });
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

    /// The GPU bytes of the smallest tile, loaded.
    pub(crate) fn smallest_tile_bytes(&self) -> u64 {
        self.tiles.iter().map(|tile| tile.bytes).min().unwrap_or(0)
    }

    /// Sets what the tiles may hold at once.
    pub(crate) fn set_budget(&mut self, bytes: u64) {
        self.budget = bytes;
    }

    /// Evicts the resident tiles `camera` (with an image `aspect` wide) no longer needs and
    /// loads the ones it needs, most needed first, until `limit` has passed (at least one
    /// each call, so that every call makes progress). Before anything changes it calls
    /// `idle`, which makes sure the GPU no longer reads what may go.
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
        let mut keep = vec![false; self.tiles.len()];
        wanted.iter().for_each(|&tile| keep[tile] = true);
        let evict: Vec<usize> = self.resident.keys().copied().filter(|&tile| !keep[tile]).collect();
        let missing: Vec<usize> =
            wanted.iter().copied().filter(|tile| !self.resident.contains_key(tile)).collect();
        if !evict.is_empty() || !missing.is_empty() {
            idle()?;
        }
        for tile in &evict {
            self.resident.remove(tile);
            self.changed = true;
        }
        let mut loaded = 0;
        let mut held: u64 = self.resident.values().map(ResidentTile::bytes).sum();
        for tile in missing {
            if loaded > 0 && limit.is_some_and(|limit| started.elapsed() >= limit) {
                break;
            }
            self.peak = self.peak.max(held + self.tiles[tile].build);
            let resident = self.load(context, tile)?;
            held += resident.bytes();
            self.peak = self.peak.max(held);
            self.resident.insert(tile, resident);
            self.changed = true;
            loaded += 1;
        }
        let in_view = (0..self.tiles.len()).filter(|&tile| seen[tile]);
        Ok(TileResidency {
            tiles: self.tiles.len(),
            resident: self.resident.len(),
            in_view: in_view.clone().count(),
            in_view_resident: in_view.filter(|tile| self.resident.contains_key(tile)).count(),
            loaded,
            evicted: evict.len(),
            pending: wanted.iter().filter(|tile| !self.resident.contains_key(tile)).count(),
            resident_bytes: held,
            budget_bytes: self.budget,
        })
    }

    /// Whether tiles were evicted or loaded since the last call: the top level must then be
    /// rebuilt, even where the update failed part way.
    pub(crate) fn take_changes(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    /// The tiles to hold, in `ranked` order: each that fits beside those before it.
    fn wanted(&self, ranked: &[usize]) -> Vec<usize> {
        let mut held = 0;
        let mut wanted = Vec::new();
        for &tile in ranked {
            let bytes = self.tiles[tile].bytes;
            if held + bytes <= self.budget {
                held += bytes;
                wanted.push(tile);
            }
        }
        wanted
    }

    fn load(&self, context: &Arc<GpuContext>, index: usize) -> Result<ResidentTile, VulkanError> {
        let tile = &self.tiles[index];
        let set = &self.sets[tile.set];
        let blas = tile_blas(context, &set.patches, tile.patches.clone(), self.layout.blas)?;
        let (addresses, buffers) = patch_records(
            context,
            &set.patches,
            tile.patches.clone(),
            self.layout.buffers,
            tile.colors.as_ref(),
        )?;
        let record = ObjectRecord {
            hot: addresses.hot,
            cold: addresses.cold,
            combined: addresses.combined,
            color_neighbors: addresses.color_neighbors,
            first_patch: tile.patches.start as u32,
            ..set.record
        };
        Ok(ResidentTile { blas, buffers, record, transform: set.transform })
    }
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
