//! How prep in bounded memory shares its budget: the reads, the sorted runs, one tile with
//! its halo at a time (while the tile before it is written), and what the store's writing
//! keeps until it finishes: the map from points to patches and the coarse level.

use pointray_io::MemoryBudget;
use pointray_patches::PrepSettings;

use crate::prep_memory::{PREP_FIXED_BYTES, prep_bytes_per_point};

/// Each input point's patch, noted while the store is written.
const PATCH_MAP_BYTES: u64 = 4;

/// The coarse level, held until the store is finished: 44 bytes a coarse patch, of which a
/// block has about one for 16 patches (6.1% on the dragon), and no more patches than input
/// points; 4 bytes a point leaves room for one coarse patch for 11 points.
const COARSE_LEVEL_BYTES: u64 = 4;

/// What writing the store holds for each input point until it finishes.
pub(crate) const STORE_BYTES_PER_POINT: u64 = PATCH_MAP_BYTES + COARSE_LEVEL_BYTES;

/// A tile is planned to own at most one in this many of the points its prep's memory holds;
/// the rest is left for its halo. Halos of 100M points sampled on the dragon held 1-2% of
/// their tiles' points; a halo that outgrows its room splits its tile.
const CORE_SHARE: u64 = 2;

/// Fewer points than this in a tile would be mostly halo.
pub(crate) const MIN_TILE_POINTS: u64 = 1024;

/// Bytes the survey and the runs take per point read at a time (the format's decoded
/// record and the cloud made of it).
const READ_BYTES_PER_POINT: u64 = 256;

/// A tile's cloud, borrowed by its prep, keeps its f64 positions (24 bytes) and each
/// member's input index (4) beside what the prep holds.
const TILE_CLOUD_BYTES: u64 = 24 + 4;

/// While a tile is prepped, the next one is gathered: its cloud (as above, with its
/// attributes), and while its halo is found, its points in f32 (12 bytes) with their reach
/// (4).
const NEXT_TILE_BYTES: u64 = TILE_CLOUD_BYTES + 12 + 4;

/// While a tile is prepped, the patches of the tile before it are written to the store: for
/// each point it owns, at most its box, hot and cold records (68 bytes), its colour
/// neighbours (48) and its input index (4).
const WRITTEN_PATCH_BYTES: u64 = 68 + 48 + 4;

#[derive(Clone, Copy, Debug)]
pub(crate) struct StreamBudget {
    /// What the work may use beyond the program itself.
    usable: u64,
    /// What each point's attributes take once read.
    attribute_bytes: u64,
}

impl StreamBudget {
    pub(crate) fn new(memory: MemoryBudget, attribute_bytes: u64) -> Self {
        Self { usable: memory.bytes.saturating_sub(PREP_FIXED_BYTES), attribute_bytes }
    }

    /// Bytes a point of a tile (owned or halo) takes while the tile is prepped and the next
    /// one gathered.
    pub(crate) fn tile_bytes_per_point(&self, settings: &PrepSettings) -> u64 {
        prep_bytes_per_point(settings, self.attribute_bytes)
            + TILE_CLOUD_BYTES
            + NEXT_TILE_BYTES
            + self.attribute_bytes
    }

    /// Points read from the input at a time: three such chunks may be held at once (one
    /// being read, one waiting, one taken), a tenth of the budget.
    pub(crate) fn chunk_points(&self) -> usize {
        (self.usable / 32 / READ_BYTES_PER_POINT).clamp(256, 1 << 20) as usize
    }

    /// Points of a COPC file's octree decoded at a time: two batches are held at once (one
    /// decoded while the one before is sorted and written), the three chunks a read may hold.
    pub(crate) fn octree_batch_points(&self) -> u64 {
        3 * self.chunk_points() as u64 / 2
    }

    /// Bytes of records sorted in memory at a time (with their keys, about half again).
    pub(crate) fn run_bytes(&self) -> usize {
        (self.usable / 3).max(1 << 20) as usize
    }

    /// The most points a tile's prep may hold, its halo included, beside the patches of a
    /// tile of `core_capacity` points being written.
    pub(crate) fn tile_capacity(&self, settings: &PrepSettings) -> u64 {
        let written = self.core_capacity(settings) * WRITTEN_PATCH_BYTES;
        self.usable.saturating_sub(written) / self.tile_bytes_per_point(settings)
    }

    /// The most points a tile may own.
    pub(crate) fn core_capacity(&self, settings: &PrepSettings) -> u64 {
        self.usable / (CORE_SHARE * self.tile_bytes_per_point(settings) + WRITTEN_PATCH_BYTES)
    }

    /// Points near a tile tested for its halo at a time (with their tree, about 64 bytes
    /// each, a tenth of the budget).
    pub(crate) fn halo_batch_points(&self) -> usize {
        (self.usable / 10 / 64).max(4096) as usize
    }

    /// Whether writing the store of `points` input points, which maps each to its patch and
    /// holds the coarse level, fits.
    pub(crate) fn holds_store_writing(&self, points: u64) -> bool {
        points.saturating_mul(STORE_BYTES_PER_POINT) <= self.usable / 2
    }

    /// What is left once what writing the store of `points` input points holds is held
    /// through the tiles' prep.
    pub(crate) fn with_store_writing(self, points: u64) -> Self {
        Self { usable: self.usable.saturating_sub(points.saturating_mul(STORE_BYTES_PER_POINT)), ..self }
    }

    /// The smallest memory budget whose tiles hold `MIN_TILE_POINTS` points of their own
    /// (`core_capacity`) beside what writing the store of `points` input points holds.
    pub(crate) fn memory_for_smallest_tile(&self, settings: &PrepSettings, points: u64) -> u64 {
        MIN_TILE_POINTS * (CORE_SHARE * self.tile_bytes_per_point(settings) + WRITTEN_PATCH_BYTES)
            + points.saturating_mul(STORE_BYTES_PER_POINT)
            + PREP_FIXED_BYTES
    }

    pub(crate) fn usable(&self) -> u64 {
        self.usable
    }
}
