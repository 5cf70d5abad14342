//! The result of `prep`: one patch per (deduplicated) point, in Morton order.

use glam::DVec3;
use pointray_kernels::{Aabb, PatchCold, PatchHot};

use crate::patch_records::PatchRecords;
use crate::prep_settings::PrepSettings;

/// Patches in local, recentred f32 coordinates; `offset` takes them back to the
/// input's coordinates (`input = local + offset`). Each section is held in memory or mapped
/// from a patch store (`PatchRecords`).
#[derive(Clone, Debug, Default, PartialEq)]
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
}

impl PatchSet {
    pub fn len(&self) -> usize {
        self.hot.len()
    }

    pub fn is_empty(&self) -> bool {
        self.hot.is_empty()
    }

    /// The union of all patch boxes, in local coordinates.
    pub fn bounds(&self) -> Option<Aabb> {
        self.aabbs.iter().copied().reduce(|a, b| a.union(&b))
    }
}
