//! A coarse grid of the space a tile's halo may occupy: the cells that the reach box of some
//! reaching point of the tile meets. A tile along the Morton curve is a few compact pieces of
//! space, so these cells hug its shape where its bounding box, which may span much of the
//! cloud, does not. Points and blocks of points outside them are skipped before any search.
//! Each marked cell is cut again into 8 x 8 x 8 fine cells, marked the same way, for the
//! points: a tile's halo is a thin shell, and the coarse cells it meets hold many times its
//! points.

use glam::{UVec3, Vec3};

/// The most cells along each axis of the grid.
const MAX_CELLS_PER_AXIS: u32 = 64;

/// Cells along each axis per cube root of the boxes (one a reaching point): eight cells a
/// box, so that a small tile's grid stays small beside its memory budget.
const CELLS_PER_CUBE_ROOT: f32 = 2.0;

/// Fine cells along each axis of a cell.
const FINE: u32 = 8;

/// One bit per fine cell of a cell: x fastest, then y, one word per z.
type FineCells = [u64; FINE as usize];

/// A cell that no box meets has no fine cells.
const NO_FINE_CELLS: u32 = u32::MAX;

pub(crate) struct ReachCells {
    /// Cells along each axis.
    side: u32,
    min: Vec3,
    /// The inverse of a cell's size along each axis.
    scale: Vec3,
    /// Per cell (x fastest), the index of its fine cells in `fine`, if some reach box meets
    /// it (the cell is marked).
    fine_index: Vec<u32>,
    fine: Vec<FineCells>,
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
        let count = (side as usize).pow(3);
        let mut cells = Self {
            side,
            min,
            scale,
            fine_index: vec![NO_FINE_CELLS; count],
            fine: Vec::new(),
            counts: Vec::new(),
        };
        for &(lo, hi) in boxes {
            cells.mark(cells.fine_cell_of(lo), cells.fine_cell_of(hi));
        }
        cells.counts = cells.summed_volume();
        cells
    }

    /// Marks the fine cells from `first` to `last`, and the cells that hold them; nothing
    /// when the box is empty.
    fn mark(&mut self, first: UVec3, last: UVec3) {
        if first.cmpgt(last).any() {
            return;
        }
        let (coarse_first, coarse_last) = (first / FINE, last / FINE);
        for z in coarse_first.z..=coarse_last.z {
            for y in coarse_first.y..=coarse_last.y {
                for x in coarse_first.x..=coarse_last.x {
                    let cell = UVec3::new(x, y, z);
                    let corner = cell * FINE;
                    let (from, to) = (first.max(corner) - corner, last.min(corner + FINE - 1) - corner);
                    let fine = self.fine_cells_of(cell);
                    let row = (u64::MAX >> (63 - (to.x - from.x))) << from.x;
                    for fine_z in from.z..=to.z {
                        for fine_y in from.y..=to.y {
                            fine[fine_z as usize] |= row << (fine_y * FINE);
                        }
                    }
                }
            }
        }
    }

    /// The fine cells of `cell`, which is marked from now on.
    fn fine_cells_of(&mut self, cell: UVec3) -> &mut FineCells {
        let index = self.index(cell);
        if self.fine_index[index] == NO_FINE_CELLS {
            self.fine_index[index] = self.fine.len() as u32;
            self.fine.push([0; FINE as usize]);
        }
        &mut self.fine[self.fine_index[index] as usize]
    }

    /// Whether `point` lies in a marked fine cell (points beyond the grid lie in its edge
    /// cells).
    pub(crate) fn contains(&self, point: Vec3) -> bool {
        let fine_cell = self.fine_cell_of(point);
        let index = self.fine_index[self.index(fine_cell / FINE)];
        if index == NO_FINE_CELLS {
            return false;
        }
        let within = fine_cell % FINE;
        self.fine[index as usize][within.z as usize] & (1 << (within.y * FINE + within.x)) != 0
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
        self.fine_cell_of(point) / FINE
    }

    /// The fine cell holding `point`, clamped to the grid; monotonic as `cell_of`.
    fn fine_cell_of(&self, point: Vec3) -> UVec3 {
        let cell = ((point - self.min) * self.scale * FINE as f32).floor().max(Vec3::ZERO);
        cell.as_uvec3().min(UVec3::splat(self.side * FINE - 1))
    }

    fn is_marked(&self, cell: UVec3) -> bool {
        self.fine_index[self.index(cell)] != NO_FINE_CELLS
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
                    let here = u32::from(self.is_marked(UVec3::new(x - 1, y - 1, z - 1)));
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
    fn only_the_fine_cells_a_box_meets_keep_points() {
        let cells = grid();
        assert!(cells.is_marked(cells.cell_of(Vec3::splat(0.3))), "the cell of the first box");
        assert!(!cells.contains(Vec3::splat(0.3)), "in that cell, away from the box");
        assert!(!cells.contains(Vec3::new(0.15, 0.15, 0.28)));
        for corner in [Vec3::splat(0.1), Vec3::splat(0.2), Vec3::new(0.1, 0.2, 0.15)] {
            assert!(cells.contains(corner), "{corner} is in the box");
        }
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
                        .any(|y| (first.x..=last.x).any(|x| cells.is_marked(UVec3::new(x, y, z))))
                });
                assert_eq!(cells.meets((lo, hi)), brute, "box {lo} to {hi}");
            }
        }
    }
}
