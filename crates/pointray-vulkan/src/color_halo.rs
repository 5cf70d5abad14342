//! The colour halo of a streamed tile: the patches outside it that a colour blend on one of
//! its patches reads (`interpolate_color`: the hit's neighbours, and theirs as the blend
//! walks toward the nearest point, `COLOR_WALK_SCANS` rings in all). A tile uploads their
//! records after its own, and its neighbour lists name them there, so that a tile blends
//! across its border as the whole set does.

use std::borrow::Cow;
use std::ops::Range;

use pointray_kernels::{COLOR_NEIGHBORS, COLOR_WALK_SCANS, NO_NEIGHBOR};
use pointray_patches::PatchSet;
use rayon::prelude::*;

/// The halo's patches, in order; a tile's buffers hold halo patch `k` at index
/// `tile.end + k`, past the tile's own.
pub(crate) struct ColorHalo {
    patches: Vec<u32>,
}

/// The halo of a set uploaded whole: none.
pub(crate) static NO_HALO: ColorHalo = ColorHalo { patches: Vec::new() };

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
        let mut records = Vec::with_capacity(range.len() + self.patches.len());
        records.extend_from_slice(&all[range]);
        records.par_extend(self.patches.par_iter().map(|&j| all[j as usize]));
        Cow::Owned(records)
    }

    /// The neighbour lists of the patches in `range`, then the halo's, naming patches of the
    /// tile by their index and those of the halo past the tile's end; neighbours beyond the
    /// halo are dropped.
    pub(crate) fn neighbor_lists<'a>(&self, patches: &'a PatchSet, range: Range<usize>) -> Cow<'a, [u32]> {
        let own = &patches.color_neighbors[range.start * COLOR_NEIGHBORS..range.end * COLOR_NEIGHBORS];
        if range == (0..patches.len()) {
            return Cow::Borrowed(own);
        }
        let local = |&j: &u32| -> u32 {
            if range.contains(&(j as usize)) {
                return j;
            }
            match self.patches.binary_search(&j) {
                Ok(k) => (range.end + k) as u32,
                Err(_) => NO_NEIGHBOR,
            }
        };
        let mut lists: Vec<u32> = own.par_iter().map(local).collect();
        lists.par_extend(
            self.patches.par_iter().flat_map_iter(|&j| neighbors_of(patches, j).iter().map(local)),
        );
        Cow::Owned(lists)
    }
}

/// Patch `patch`'s neighbour list.
fn neighbors_of(patches: &PatchSet, patch: u32) -> &[u32] {
    let start = patch as usize * COLOR_NEIGHBORS;
    &patches.color_neighbors[start..start + COLOR_NEIGHBORS]
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use pointray_kernels::{PatchCold, PatchHot, interpolate_color};

    use super::*;

    const SIDE: u32 = 30;

    /// A `SIDE` x `SIDE` grid of patches a unit apart, each listing the neighbours on its
    /// four sides and two of its diagonals (the rest of its list empty), its colour a gradient over the grid.
    fn coloured_grid() -> PatchSet {
        let cell = |i: u32| (i % SIDE, i / SIDE);
        let hot: Vec<PatchHot> = (0..SIDE * SIDE)
            .map(|i| Vec3::new(cell(i).0 as f32, cell(i).1 as f32, 0.0))
            .map(|origin| PatchHot::isotropic(origin, Vec3::X, Vec3::Z, [0.0; 6], 1.0))
            .collect();
        let color = |(x, y): (u32, u32)| (x * 8) | (y * 8) << 8 | ((x * y) % 256) << 16 | 0xff00_0000;
        let cold: Vec<PatchCold> = (0..SIDE * SIDE)
            .map(|i| PatchCold { color_rgba8: color(cell(i)), intensity: 0.0, color_reach: 1.2 })
            .collect();
        let offsets = [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1)];
        let neighbor = |i: u32, (dx, dy): (i32, i32)| {
            let (x, y) = (cell(i).0 as i32 + dx, cell(i).1 as i32 + dy);
            let inside = (0..SIDE as i32).contains(&x) && (0..SIDE as i32).contains(&y);
            if inside { y as u32 * SIDE + x as u32 } else { NO_NEIGHBOR }
        };
        let list = |i: u32| {
            let mut list = [NO_NEIGHBOR; COLOR_NEIGHBORS];
            list.iter_mut().zip(offsets).for_each(|(slot, offset)| *slot = neighbor(i, offset));
            list
        };
        let lists: Vec<u32> = (0..SIDE * SIDE).flat_map(list).collect();
        let aabbs = vec![Default::default(); hot.len()];
        PatchSet {
            hot: hot.into(),
            cold: cold.into(),
            aabbs: aabbs.into(),
            color_neighbors: lists.into(),
            ..PatchSet::default()
        }
    }

    #[test]
    fn a_tile_with_its_halo_blends_at_its_border_as_the_whole_set_does() {
        let patches = coloured_grid();
        let range = (10 * SIDE) as usize..(20 * SIDE) as usize;
        let halo = ColorHalo::new(&patches, range.clone());
        // The tile as its buffers read it. Below its start lie black points where the grid's
        // are, so that a blend reading there would change colour.
        let black = PatchCold { color_rgba8: 0xff00_0000, intensity: 0.0, color_reach: 1.2 };
        let hot: Vec<PatchHot> = patches.hot[..range.start]
            .iter()
            .copied()
            .chain(halo.records(&patches.hot, range.clone()).iter().copied())
            .collect();
        let cold: Vec<PatchCold> = std::iter::repeat_n(black, range.start)
            .chain(halo.records(&patches.cold, range.clone()).iter().copied())
            .collect();
        let lists: Vec<u32> = std::iter::repeat_n(NO_NEIGHBOR, range.start * COLOR_NEIGHBORS)
            .chain(halo.neighbor_lists(&patches, range.clone()).iter().copied())
            .collect();
        // Hits on the tile's first and last rows, blended up to three rows past its border,
        // where the blend walks three scans out.
        let rows = [(10, -1.0), (19, 1.0)];
        for (row, outward) in rows {
            for x in 0..SIDE {
                let hit = row * SIDE + x;
                for (step, across) in [0.0, 0.6, 1.6, 2.4].into_iter().zip([0.3, -0.3, 0.2, -0.2]) {
                    let position = Vec3::new(x as f32 + across, row as f32 + outward * step, 0.0);
                    let whole = interpolate_color(
                        position,
                        hit,
                        &patches.hot,
                        &patches.cold,
                        &patches.color_neighbors,
                    );
                    let tile = interpolate_color(position, hit, &hot, &cold, &lists);
                    assert_eq!(tile, whole, "hit {hit} at {position}");
                }
            }
        }
    }

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
        let hot = vec![PatchHot::default(); 10];
        PatchSet { hot: hot.into(), color_neighbors: lists.into(), ..PatchSet::default() }
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
        let whole = ColorHalo::new(&patches, 0..10);
        assert_eq!(whole.len(), 0, "a whole set has none");
        assert!(matches!(whole.neighbor_lists(&patches, 0..10), Cow::Borrowed(_)), "and keeps its lists");
    }
}
