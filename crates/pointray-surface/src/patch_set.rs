//! The result of `prep`: one patch per (deduplicated) point, in Morton order.

use glam::DVec3;
use pointray_kernels::{Aabb, COLOR_NEIGHBORS, PatchCold, PatchHot};

use crate::patch_bounds::BoxKind;

/// The settings `prep` ran with; stored in the patch store's header.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrepParams {
    /// Neighbours used for the support radius and the quadratic fit (SPEC.md §2.1).
    pub k: u32,
    /// Neighbours used for the PCA normal (SPEC.md §2.2).
    pub normal_k: u32,
    /// The box each patch gets (SPEC.md §2.4).
    pub box_kind: BoxKind,
    /// Points closer than this fraction of the bounding-box diagonal are merged as
    /// duplicates; 1e-6 is about ten f32 ulps of the recentred coordinates.
    pub duplicate_tolerance: f32,
    /// How far each patch reaches, as a fraction of the paper's `d_i` (SPEC.md §2.3): the
    /// stored radius, and so the disk, the box and the self-clearance, is `disk_scale d_i`.
    /// The fit still uses the whole neighbourhood. 1 is the paper.
    pub disk_scale: f32,
}

impl Default for PrepParams {
    fn default() -> Self {
        Self { k: 9, normal_k: 16, box_kind: BoxKind::Tight, duplicate_tolerance: 1e-6, disk_scale: 1.0 }
    }
}

/// Patches in local, recentred f32 coordinates; `offset` takes them back to the
/// input's coordinates (`input = local + offset`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatchSet {
    pub params: PrepParams,
    pub offset: DVec3,
    pub aabbs: Vec<Aabb>,
    pub hot: Vec<PatchHot>,
    pub cold: Vec<PatchCold>,
    /// `COLOR_NEIGHBORS` patch indices per patch, nearest first, `NO_NEIGHBOR` in unused
    /// slots: the points a hit's colour is blended from (`interpolate_color`). Empty when
    /// the cloud has neither colours nor intensities, as there is nothing to blend.
    pub color_neighbors: Vec<u32>,
}

impl PatchSet {
    pub fn len(&self) -> usize {
        self.hot.len()
    }

    pub fn is_empty(&self) -> bool {
        self.hot.is_empty()
    }

    /// Patch `i`'s colour neighbours; empty when the set keeps none.
    pub fn color_neighbors_of(&self, i: usize) -> &[u32] {
        self.color_neighbors.get(i * COLOR_NEIGHBORS..(i + 1) * COLOR_NEIGHBORS).unwrap_or(&[])
    }

    /// The union of all patch boxes, in local coordinates.
    pub fn bounds(&self) -> Option<Aabb> {
        self.aabbs.iter().copied().reduce(|a, b| a.union(&b))
    }
}
