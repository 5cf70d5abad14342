//! A large patch set split into tiles, each small enough for one bottom-level acceleration
//! structure (a device's `maxPrimitiveCount`; lavapipe's is 2^24 - 1). Patches are stored in
//! Morton order of their points, so a run of consecutive patches covers a compact region:
//! a tile is such a run, and the tiles' boxes overlap little. Both renderers tile the same
//! way and report a tile's hits by the patch's index in the whole set.

use std::ops::Range;

/// The runs of `patch_count` patches, at most `max_patches` each (0 counts as 1), of
/// near-equal length, in order; none when there are no patches.
pub fn tile_ranges(patch_count: usize, max_patches: usize) -> Vec<Range<usize>> {
    even_ranges(patch_count, patch_count.div_ceil(max_patches.max(1)))
}

/// `count` items in `parts` consecutive runs whose lengths differ by one at most.
pub fn even_ranges(count: usize, parts: usize) -> Vec<Range<usize>> {
    let start = |part: usize| (part as u128 * count as u128 / parts.max(1) as u128) as usize;
    (0..parts).map(|part| start(part)..start(part + 1)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_every_patch_once_within_the_limit() {
        for (count, max) in
            [(0, 5), (1, 5), (5, 5), (6, 5), (1000, 7), (1000, 1), (7, 0), (16_777_216, 16_777_215)]
        {
            let tiles = tile_ranges(count, max);
            assert_eq!(tiles.len(), count.div_ceil(max.max(1)), "{count} patches, at most {max}");
            assert!(tiles.iter().all(|tile| !tile.is_empty() && tile.len() <= max.max(1)), "{tiles:?}");
            let mut next = 0;
            for tile in &tiles {
                assert_eq!(tile.start, next, "{tiles:?}");
                next = tile.end;
            }
            assert_eq!(next, count);
            let (shortest, longest) =
                (tiles.iter().map(|t| t.len()).min(), tiles.iter().map(|t| t.len()).max());
            assert!(longest.unwrap_or(0) - shortest.unwrap_or(0) <= 1, "near-equal: {tiles:?}");
        }
    }
}
