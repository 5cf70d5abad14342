//! The possible duplicates split into clusters that the greedy merge can take one at a
//! time, and so in parallel: a point's duplicates lie in its own fine cell or the 26 around
//! it, so points whose occupied cells do not touch never interact.

use std::ops::Range;

use rayon::prelude::*;

/// A fine cell's coordinates; cells sort by x, then y, then z, so that one row of cells
/// (same x and y) is contiguous.
pub(crate) type CellKey = [i32; 3];

/// The points of every cluster that could merge anything (a cell holding several points,
/// or cells touching each other), each cluster in input order:
/// `members[starts[c]..starts[c + 1]]`. A point in no cluster is alone and stays.
pub(crate) struct Clusters {
    members: Vec<u32>,
    starts: Vec<usize>,
}

impl Clusters {
    /// Groups `keyed` (each point's fine cell and index); cells touch when they differ by at
    /// most one in each coordinate, unless `touching` is false (exact duplicates only).
    pub(crate) fn of(mut keyed: Vec<(CellKey, u32)>, touching: bool) -> Self {
        keyed.par_sort_unstable();
        let cells = CellRuns::new(keyed);
        let pairs = if touching { cells.touching_pairs() } else { Vec::new() };
        let roots = ComponentRoots::of(cells.len(), &pairs);
        let mut grouped: Vec<(u32, u32)> = (0..cells.len())
            .into_par_iter()
            .filter(|&c| cells.run(c).len() > 1 || roots.is_linked(c))
            .flat_map_iter(|c| {
                let root = roots.root(c);
                cells.run(c).iter().map(move |&(_, point)| (root, point))
            })
            .collect();
        grouped.par_sort_unstable();
        let starts = (0..=grouped.len())
            .filter(|&i| i == 0 || i == grouped.len() || grouped[i].0 != grouped[i - 1].0)
            .collect();
        Self { members: grouped.into_iter().map(|(_, point)| point).collect(), starts }
    }

    pub(crate) fn par_iter(&self) -> impl IndexedParallelIterator<Item = &[u32]> {
        let count = self.starts.len().saturating_sub(1);
        (0..count).into_par_iter().map(|c| &self.members[self.starts[c]..self.starts[c + 1]])
    }
}

/// Points sorted by cell, and where each occupied cell's run of points starts.
struct CellRuns {
    keyed: Vec<(CellKey, u32)>,
    /// One entry per occupied cell, then `keyed.len()`.
    starts: Vec<usize>,
}

/// Cells swept per parallel task when looking for touching cells.
const SWEEP_CHUNK: usize = 1 << 14;

/// The rows of cells after a cell's own row in sort order that can touch it, as (dx, dy);
/// its own row comes first, where only the next cell along z can touch it.
const LATER_ROWS: [(i64, i64); 5] = [(0, 0), (0, 1), (1, -1), (1, 0), (1, 1)];

impl CellRuns {
    fn new(keyed: Vec<(CellKey, u32)>) -> Self {
        let starts = (0..=keyed.len())
            .into_par_iter()
            .filter(|&i| i == 0 || i == keyed.len() || keyed[i].0 != keyed[i - 1].0)
            .collect();
        Self { keyed, starts }
    }

    fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    fn run(&self, cell: usize) -> &[(CellKey, u32)] {
        &self.keyed[self.starts[cell]..self.starts[cell + 1]]
    }

    /// Cell coordinates widened, so that neighbouring coordinates never overflow.
    fn key(&self, cell: usize) -> [i64; 3] {
        self.keyed[self.starts[cell]].0.map(i64::from)
    }

    /// The first cell whose key is not below `key` (binary search).
    fn first_at_or_after(&self, key: [i64; 3]) -> usize {
        let (mut low, mut high) = (0, self.len());
        while low < high {
            let middle = (low + high) / 2;
            if self.key(middle) < key {
                low = middle + 1;
            } else {
                high = middle;
            }
        }
        low
    }

    /// Every pair of touching occupied cells once, as (earlier, later) in sort order.
    fn touching_pairs(&self) -> Vec<(u32, u32)> {
        let chunks = self.len().div_ceil(SWEEP_CHUNK);
        (0..chunks)
            .into_par_iter()
            .flat_map_iter(|chunk| {
                let cells = chunk * SWEEP_CHUNK..((chunk + 1) * SWEEP_CHUNK).min(self.len());
                LATER_ROWS.into_iter().flat_map(move |row| self.sweep_row(cells.clone(), row))
            })
            .collect()
    }

    /// The cells of row offset `(dx, dy)` that touch each of `cells`. The window's start
    /// only moves forward as the cells do, so the sweep is linear.
    fn sweep_row(&self, cells: Range<usize>, (dx, dy): (i64, i64)) -> Vec<(u32, u32)> {
        let first_dz = if (dx, dy) == (0, 0) { 1 } else { -1 };
        let window = |[x, y, z]: [i64; 3]| ([x + dx, y + dy, z + first_dz], [x + dx, y + dy, z + 1]);
        let Some(first) = cells.clone().next() else {
            return Vec::new();
        };
        let mut next = self.first_at_or_after(window(self.key(first)).0);
        let mut pairs = Vec::new();
        for cell in cells {
            let (low, high) = window(self.key(cell));
            while next < self.len() && self.key(next) < low {
                next += 1;
            }
            let touching = (next..self.len()).take_while(|&other| self.key(other) <= high);
            pairs.extend(touching.map(|other| (cell as u32, other as u32)));
        }
        pairs
    }
}

/// Connected components of the touching cells (union-find).
struct ComponentRoots {
    parent: Vec<u32>,
    linked: Vec<bool>,
}

impl ComponentRoots {
    fn of(cell_count: usize, pairs: &[(u32, u32)]) -> Self {
        let mut roots = Self { parent: (0..cell_count as u32).collect(), linked: vec![false; cell_count] };
        for &(a, b) in pairs {
            let (ra, rb) = (roots.find(a), roots.find(b));
            roots.parent[ra.max(rb) as usize] = ra.min(rb);
            roots.linked[a as usize] = true;
            roots.linked[b as usize] = true;
        }
        for &(a, b) in pairs {
            for cell in [a, b] {
                roots.parent[cell as usize] = roots.find(cell);
            }
        }
        roots
    }

    /// Follows parents to the root, halving the path on the way.
    fn find(&mut self, mut cell: u32) -> u32 {
        while self.parent[cell as usize] != cell {
            let grandparent = self.parent[self.parent[cell as usize] as usize];
            self.parent[cell as usize] = grandparent;
            cell = grandparent;
        }
        cell
    }

    fn is_linked(&self, cell: usize) -> bool {
        self.linked[cell]
    }

    /// The root of `cell`'s component (every linked cell points at its root once built).
    fn root(&self, cell: usize) -> u32 {
        self.parent[cell]
    }
}
