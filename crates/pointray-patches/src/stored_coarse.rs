//! The coarse level (`coarse_level`) as the patch store holds it: each block's count of
//! coarse patches (u32), then each coarse patch's hot and cold records (44 bytes; its box is
//! made again, as the compact records' are). Writers make it from the records as the store
//! keeps them, decoded, so that a renderer reading it gets the very level it would make from
//! the patches it reads, without the 300 ns a patch that making it costs.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use pointray_kernels::{Aabb, PatchCold, PatchHot};
use rayon::prelude::*;

use crate::coarse_level::{CoarseLevel, coarse_block, coarse_set};
use crate::compact_patches::{
    BLOCK_PATCHES, BlockFrame, CompactColor, CompactPatch, decode_block, encode_colors, encode_patches,
};
use crate::patch_set::PatchSet;
use crate::prep_settings::BoxKind;

/// One coarse patch as stored. 44 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CoarseRecord {
    pub hot: PatchHot,
    pub cold: PatchCold,
}

/// The coarse level of a run of whole blocks, as the store holds it.
#[derive(Debug, Default)]
pub struct StoredCoarse {
    /// The coarse patches of each block.
    pub counts: Vec<u32>,
    pub records: Vec<CoarseRecord>,
}

impl StoredCoarse {
    /// The coarse level of `hot` and `cold`, whose first patch starts a block and whose
    /// blocks `frames` frames, as a compact store with colour columns where `colors` keeps
    /// them: each block encoded, decoded and merged, on every core.
    pub fn of_blocks(frames: &[BlockFrame], hot: &[PatchHot], cold: &[PatchCold], colors: bool) -> Self {
        let blocks: Vec<Vec<(PatchHot, PatchCold)>> = (frames.par_iter().enumerate())
            .map(|(block, frame)| {
                let range = block * BLOCK_PATCHES..((block + 1) * BLOCK_PATCHES).min(hot.len());
                let (hot, cold) = as_stored_block(frame, &hot[range.clone()], &cold[range], colors);
                coarse_block(&hot, &cold)
            })
            .collect();
        let counts = blocks.iter().map(|block| block.len() as u32).collect();
        let records = blocks.into_iter().flatten().map(|(hot, cold)| CoarseRecord { hot, cold }).collect();
        Self { counts, records }
    }

    /// Appends the level of the blocks after these.
    pub fn extend(&mut self, after: Self) {
        self.counts.extend(after.counts);
        self.records.extend(after.records);
    }
}

/// One block's records as a compact store gives them back.
fn as_stored_block(
    frame: &BlockFrame,
    hot: &[PatchHot],
    cold: &[PatchCold],
    colors: bool,
) -> (Vec<PatchHot>, Vec<PatchCold>) {
    let n = hot.len();
    let mut compact = vec![CompactPatch::default(); n];
    encode_patches(frame, hot, cold, &mut compact);
    let stored_colors = colors.then(|| {
        let mut out = vec![CompactColor::default(); n];
        encode_colors(cold, &mut out);
        out
    });
    let (mut hot, mut cold) = (vec![PatchHot::zeroed(); n], vec![PatchCold::zeroed(); n]);
    // The boxes are not kept: a coarse patch's box is made from it.
    let mut aabbs = vec![Aabb::zeroed(); n];
    decode_block(frame, &compact, stored_colors.as_deref(), BoxKind::Cube, (&mut hot, &mut aabbs, &mut cold));
    (hot, cold)
}

/// The coarse level of `fine` that a store's sections hold (`counts`, one a block, and
/// `records`), or why it is not one.
pub fn level_of_sections(
    counts: &[u32],
    records: &[CoarseRecord],
    fine: &PatchSet,
) -> Result<Arc<CoarseLevel>, String> {
    let (hot, cold) = records.iter().map(|record| (record.hot, record.cold)).unzip();
    let coarse = coarse_set(fine, hot, cold);
    coarse.check().map_err(|problem| format!("the coarse level: {problem}"))?;
    CoarseLevel::of_blocks(coarse, counts)
        .map(Arc::new)
        .ok_or_else(|| "the coarse level's block counts do not add up to its patches".into())
}
