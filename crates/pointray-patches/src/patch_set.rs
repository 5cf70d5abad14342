//! The result of `prep`: one patch per (deduplicated) point, in Morton order.

use std::sync::Arc;

use glam::DVec3;
use pointray_kernels::{Aabb, PatchCold, PatchHot};

use crate::coarse_level::CoarseLevel;
use crate::patch_records::PatchRecords;
use crate::prep_settings::PrepSettings;

/// Patches in local, recentred f32 coordinates; `offset` takes them back to the
/// input's coordinates (`input = local + offset`). Each section is held in memory or mapped
/// from a patch store (`PatchRecords`).
#[derive(Clone, Debug, Default)]
pub struct PatchSet {
    /// The settings `prep` ran with; stored in the patch store's header.
    pub settings: PrepSettings,
    pub offset: DVec3,
    pub aabbs: PatchRecords<Aabb>,
    pub hot: PatchRecords<PatchHot>,
    pub cold: PatchRecords<PatchCold>,
    /// `COLOR_NEIGHBORS` patch indices per patch, nearest first, `NO_NEIGHBOR` in unused
    /// slots: the points a hit's colour is blended from (`interpolate_color`). Empty when
    /// the cloud has neither colours nor intensities, as there is nothing to blend.
    pub color_neighbors: PatchRecords<u32>,
    /// The coarse level a patch store held beside these patches; `None` for a set made in
    /// memory, whose renderer makes it (`CoarseLevel::of`) where it needs one. Whoever
    /// changes the records leaves it `None`.
    pub coarse: Option<Arc<CoarseLevel>>,
}

/// Sets are equal when their patches are: the coarse level is made from them.
impl PartialEq for PatchSet {
    fn eq(&self, other: &Self) -> bool {
        self.settings == other.settings
            && self.offset == other.offset
            && self.aabbs == other.aabbs
            && self.hot == other.hot
            && self.cold == other.cold
            && self.color_neighbors == other.color_neighbors
    }
}

impl PatchSet {
    pub fn len(&self) -> usize {
        self.hot.len()
    }

    pub fn is_empty(&self) -> bool {
        self.hot.is_empty()
    }

    /// The coarse level: the stored one, else one made now.
    pub fn coarse_level(&self) -> Arc<CoarseLevel> {
        self.coarse.clone().unwrap_or_else(|| Arc::new(CoarseLevel::of(self)))
    }

    /// The union of all patch boxes, in local coordinates.
    pub fn bounds(&self) -> Option<Aabb> {
        self.aabbs.iter().copied().reduce(|a, b| a.union(&b))
    }
}
