//! A coarse grid of the space a tile's halo may occupy: the cells that the reach box of some
//! run of the tile's points meets. A tile along the Morton curve is a few compact pieces of
//! space, so these cells hug its shape where its bounding box, which may span much of the
//! cloud, does not. Points and blocks of points outside them are skipped before any search.

use glam::{UVec3, Vec3};

/// The most cells along each axis of the grid.
const MAX_CELLS_PER_AXIS: u32 = 64;

/// Cells along each axis per cube root of the boxes: eight cells a box, so that a
/// small tile's grid stays small beside its memory budget.
const CELLS_PER_CUBE_ROOT: f32 = 2.0;

pub(crate) struct ReachCells {
    /// Cells along each axis.
    side: u32,
    min: Vec3,
    /// The inverse of a cell's size along each axis.
    scale: Vec3,
    /// Per cell (x fastest), whether some reach box meets it.
    marked: Vec<bool>,
    /// The marked cells in the box from the origin cell to each cell, inclusive, at index
    /// `cell + 1` along each axis (a summed-volume table), so any box of cells is counted
    /// in constant time.
    counts: Vec<u32>,
}

impl ReachCells {
    /// The grid over `bounds` with the cells that any of `boxes` meets marked.
    pub(crate) fn new((min, max): (Vec3, Vec3), boxes: &[(Vec3, Vec3)]) -> Self {
        let side = ((boxes.len() as f32).cbrt() * CELLS_PER_CUBE_ROOT)
            .ceil()
            .clamp(1.0, MAX_CELLS_PER_AXIS as f32) as u32;
        let extent = (max - min).max(Vec3::splat(f32::MIN_POSITIVE));
        let scale = Vec3::splat(side as f32) / extent;
        let marked = vec![false; (side as usize).pow(3)];
        let mut cells = Self { side, min, scale, marked, counts: Vec::new() };
        for &(lo, hi) in boxes {
            let (first, last) = (cells.cell_of(lo), cells.cell_of(hi));
            for z in first.z..=last.z {
                for y in first.y..=last.y {
                    let row = cells.index(UVec3::new(0, y, z));
                    cells.marked[row + first.x as usize..=row + last.x as usize].fill(true);
                }
            }
        }
        cells.counts = cells.summed_volume();
        cells
    }

    /// Whether `point` lies in a marked cell (points beyond the grid lie in its edge cells).
    pub(crate) fn contains(&self, point: Vec3) -> bool {
        self.marked[self.index(self.cell_of(point))]
    }

    /// Whether the box from `lo` to `hi` meets a marked cell.
    pub(crate) fn meets(&self, (lo, hi): (Vec3, Vec3)) -> bool {
        let (first, last) = (self.cell_of(lo), self.cell_of(hi) + UVec3::ONE);
        let at = |x: u32, y: u32, z: u32| i64::from(self.counts[self.summed_index(UVec3::new(x, y, z))]);
        let (a, b) = (first, last);
        let inside = at(b.x, b.y, b.z) - at(a.x, b.y, b.z) - at(b.x, a.y, b.z) - at(b.x, b.y, a.z)
            + at(a.x, a.y, b.z)
            + at(a.x, b.y, a.z)
            + at(b.x, a.y, a.z)
            - at(a.x, a.y, a.z);
        inside > 0
    }

    /// The cell holding `point`, clamped to the grid. Monotonic in each coordinate, so every
    /// point of a box lies in the cells from its corners' cells.
    fn cell_of(&self, point: Vec3) -> UVec3 {
        let cell = ((point - self.min) * self.scale).floor().max(Vec3::ZERO);
        cell.as_uvec3().min(UVec3::splat(self.side - 1))
    }

    fn index(&self, cell: UVec3) -> usize {
        let n = self.side as usize;
        (cell.z as usize * n + cell.y as usize) * n + cell.x as usize
    }

    /// Index into the summed-volume table, one wider than the grid along each axis.
    fn summed_index(&self, corner: UVec3) -> usize {
        let n = self.side as usize + 1;
        (corner.z as usize * n + corner.y as usize) * n + corner.x as usize
    }

    /// `table[summed_index(c)]` counts the marked cells below `c` along every axis.
    fn summed_volume(&self) -> Vec<u32> {
        let n = self.side;
        let mut table = vec![0u32; (n as usize + 1).pow(3)];
        for z in 1..=n {
            for y in 1..=n {
                for x in 1..=n {
                    let here = u32::from(self.marked[self.index(UVec3::new(x - 1, y - 1, z - 1))]);
                    let at = |dx: u32, dy: u32, dz: u32| {
                        table[self.summed_index(UVec3::new(x - dx, y - dy, z - dz))]
                    };
                    table[self.summed_index(UVec3::new(x, y, z))] =
                        here + at(1, 0, 0) + at(0, 1, 0) + at(0, 0, 1)
                            - at(1, 1, 0)
                            - at(1, 0, 1)
                            - at(0, 1, 1)
                            + at(1, 1, 1);
                }
            }
        }
        table
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> ReachCells {
        let boxes =
            [(Vec3::splat(0.1), Vec3::splat(0.2)), (Vec3::new(0.9, 0.0, 0.5), Vec3::new(1.0, 0.05, 0.6))];
        ReachCells::new((Vec3::ZERO, Vec3::ONE), &boxes)
    }

    #[test]
    fn points_in_a_reach_box_are_kept_and_points_far_from_all_are_not() {
        let cells = grid();
        assert!(cells.contains(Vec3::splat(0.15)));
        assert!(cells.contains(Vec3::new(0.95, 0.01, 0.55)));
        assert!(cells.contains(Vec3::new(1.5, -1.0, 0.55)), "beyond the grid, in an edge cell");
        assert!(!cells.contains(Vec3::splat(0.5)));
        assert!(!cells.contains(Vec3::new(0.15, 0.15, 0.9)));
    }

    #[test]
    fn a_box_meets_the_grid_exactly_where_it_meets_a_marked_cell() {
        let cells = grid();
        let samples: Vec<Vec3> = (0..12)
            .flat_map(|z| {
                (0..12)
                    .flat_map(move |y| (0..12).map(move |x| Vec3::new(x as f32, y as f32, z as f32) / 11.0))
            })
            .collect();
        for (i, &lo) in samples.iter().enumerate().step_by(7) {
            for &hi in samples.iter().skip(i).step_by(13) {
                let hi = lo.max(hi);
                let (first, last) = (cells.cell_of(lo), cells.cell_of(hi));
                let brute = (first.z..=last.z).any(|z| {
                    (first.y..=last.y)
                        .any(|y| (first.x..=last.x).any(|x| cells.marked[cells.index(UVec3::new(x, y, z))]))
                });
                assert_eq!(cells.meets((lo, hi)), brute, "box {lo} to {hi}");
            }
        }
    }
}
