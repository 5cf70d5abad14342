//! The colour halo of a streamed tile: the patches outside it that a colour blend on one of
//! its patches reads (`interpolate_color`: the hit's neighbours, and theirs as the blend
//! walks toward the nearest point, `COLOR_WALK_SCANS` rings in all). A tile uploads their
//! records after its own, and its neighbour lists name them there, so that a tile blends
//! across its border as the whole set does.

use std::borrow::Cow;
use std::ops::Range;

use pointray_kernels::{COLOR_NEIGHBORS, COLOR_WALK_SCANS, NO_NEIGHBOR};
use pointray_surface::PatchSet;
use rayon::prelude::*;

/// The halo's patches, in order; a tile's buffers hold halo patch `k` at index
/// `tile.end + k`, past the tile's own.
#[derive(Default)]
pub(crate) struct ColorHalo {
    patches: Vec<u32>,
}

impl ColorHalo {
    /// The halo of the patches in `range` of `patches`; empty for a whole set, and for a set
    /// without neighbour lists.
    pub(crate) fn new(patches: &PatchSet, range: Range<usize>) -> Self {
        let mut halo = Self { patches: Vec::new() };
        if patches.color_neighbors.is_empty() || range == (0..patches.len()) {
            return halo;
        }
        let mut ring: Vec<u32> = (range.start as u32..range.end as u32).collect();
        for _ in 0..COLOR_WALK_SCANS {
            ring = halo.next_ring(patches, &range, &ring);
            halo.patches.extend_from_slice(&ring);
            halo.patches.par_sort_unstable();
        }
        // The halo's indices run on past the tile's; none may read as "no neighbour".
        if range.end + halo.patches.len() >= NO_NEIGHBOR as usize {
            halo.patches.clear();
        }
        halo
    }

    /// The patches outside `range` and outside the halo so far that `ring` names.
    fn next_ring(&self, patches: &PatchSet, range: &Range<usize>, ring: &[u32]) -> Vec<u32> {
        let mut next: Vec<u32> = ring
            .par_iter()
            .flat_map_iter(|&patch| neighbors_of(patches, patch).iter().copied())
            .filter(|&j| j != NO_NEIGHBOR && !range.contains(&(j as usize)))
            .filter(|j| self.patches.binary_search(j).is_err())
            .collect();
        next.par_sort_unstable();
        next.dedup();
        next
    }

    pub(crate) fn len(&self) -> usize {
        self.patches.len()
    }

    /// The records of the patches in `range` of `all`, then the halo's.
    pub(crate) fn records<'a, T: Copy + Send + Sync>(
        &self,
        all: &'a [T],
        range: Range<usize>,
    ) -> Cow<'a, [T]> {
        if self.patches.is_empty() {
            return Cow::Borrowed(&all[range]);
        }
        let halo = self.patches.iter().map(|&j| all[j as usize]);
        Cow::Owned(all[range].iter().copied().chain(halo).collect())
    }

    /// The neighbour lists of the patches in `range`, then the halo's, naming patches of the
    /// tile by their index and those of the halo past the tile's end; neighbours beyond the
    /// halo are dropped.
    pub(crate) fn neighbor_lists<'a>(&self, patches: &'a PatchSet, range: Range<usize>) -> Cow<'a, [u32]> {
        let own = &patches.color_neighbors[range.start * COLOR_NEIGHBORS..range.end * COLOR_NEIGHBORS];
        if range == (0..patches.len()) {
            return Cow::Borrowed(own);
        }
        let halo = self.patches.iter().flat_map(|&j| neighbors_of(patches, j).iter());
        let local = |&j: &u32| -> u32 {
            if range.contains(&(j as usize)) {
                return j;
            }
            match self.patches.binary_search(&j) {
                Ok(k) => (range.end + k) as u32,
                Err(_) => NO_NEIGHBOR,
            }
        };
        Cow::Owned(own.iter().chain(halo).map(local).collect())
    }
}

/// Patch `patch`'s neighbour list.
fn neighbors_of(patches: &PatchSet, patch: u32) -> &[u32] {
    let start = patch as usize * COLOR_NEIGHBORS;
    &patches.color_neighbors[start..start + COLOR_NEIGHBORS]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ten patches in a row, each naming the one before and after it.
    fn row() -> PatchSet {
        let lists = (0..10u32)
            .flat_map(|i| {
                let mut list = [NO_NEIGHBOR; COLOR_NEIGHBORS];
                list[0] = i.checked_sub(1).unwrap_or(NO_NEIGHBOR);
                list[1] = if i < 9 { i + 1 } else { NO_NEIGHBOR };
                list
            })
            .collect::<Vec<u32>>();
        PatchSet { color_neighbors: lists.into(), ..PatchSet::default() }
    }

    #[test]
    fn a_tile_holds_the_rings_a_blend_walks_and_names_them_past_its_end() {
        let patches = row();
        let halo = ColorHalo::new(&patches, 4..6);
        assert_eq!(halo.patches, [1, 2, 3, 6, 7, 8], "three rings on either side");
        let values: Vec<u32> = (0..10).collect();
        assert_eq!(*halo.records(&values, 4..6), [4, 5, 1, 2, 3, 6, 7, 8]);
        let lists = halo.neighbor_lists(&patches, 4..6);
        let pair = |patch: usize| (lists[patch * COLOR_NEIGHBORS], lists[patch * COLOR_NEIGHBORS + 1]);
        assert_eq!(pair(0), (8, 5), "patch 4: patch 3 is the halo's third, at 6 + 2");
        assert_eq!(pair(1), (4, 9), "patch 5: patch 6 is the halo's fourth");
        assert_eq!(pair(2), (NO_NEIGHBOR, 7), "patch 1: patch 0 lies beyond the halo");
        assert_eq!(pair(7), (10, NO_NEIGHBOR), "patch 8: patch 7 at 6 + 4, patch 9 beyond the halo");
        assert_eq!(ColorHalo::new(&patches, 0..10).len(), 0, "a whole set has none");
    }
}
