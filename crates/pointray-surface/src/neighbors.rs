//! The k-nearest-neighbour table (METHOD.md §2.1), shared by normals, orientation and the fit.

use std::num::NonZeroUsize;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use crate::nearest_cells::{Blocks, CellGrid};

/// `k` neighbours per point in one flat table. Row `i` lists point `i`'s neighbours by
/// increasing Euclidean distance and never contains `i` itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Neighbors {
    pub k: usize,
    pub indices: Vec<u32>,
    pub distances: Vec<f32>,
}

impl Neighbors {
    /// Point `i`'s neighbours, nearest first.
    pub fn of(&self, i: usize) -> &[u32] {
        &self.indices[i * self.k..(i + 1) * self.k]
    }

    /// The distances to `of(i)`, in the same order.
    pub fn distances_of(&self, i: usize) -> &[f32] {
        &self.distances[i * self.k..(i + 1) * self.k]
    }

    pub fn point_count(&self) -> usize {
        self.indices.len().checked_div(self.k).unwrap_or(0)
    }

    /// Keeps only the nearest `k` of each row (no change when rows are not wider), and
    /// gives the rest of the memory back: the later stages need fewer neighbours than the
    /// normals did.
    pub fn narrow(&mut self, k: usize) {
        if k >= self.k {
            return;
        }
        let rows = self.point_count();
        // Row `i` moves down to `i * k`, never past a row not yet moved.
        for i in 0..rows {
            self.indices.copy_within(i * self.k..i * self.k + k, i * k);
            self.distances.copy_within(i * self.k..i * self.k + k, i * k);
        }
        self.indices.truncate(rows * k);
        self.indices.shrink_to_fit();
        self.distances.truncate(rows * k);
        self.distances.shrink_to_fit();
        self.k = k;
    }
}

/// Points per rayon task: large enough to amortise scheduling, small enough to balance.
const CHUNK: usize = 4096;

/// The wider blocks are tried when at most one query in this many is left by the near ones.
const FEW_LEFT: usize = 64;

/// The `k` nearest neighbours of every point, in parallel: from a grid of cells where it can
/// tell them for sure (`nearest_cells`), else from a k-d tree.
///
/// Callers guarantee `points.len() > k` and fewer than `u32::MAX` points. Should a row
/// still come up short, it is padded by repeating its farthest neighbour so the table
/// keeps its shape. Coincident points are neighbours of each other at distance 0; equally
/// distant neighbours come in index order.
pub fn k_nearest(points: &[Vec3], k: usize) -> Neighbors {
    if k == 0 || points.is_empty() {
        return Neighbors { k, ..Neighbors::default() };
    }
    let grid = CellGrid::new(points, k + 1);
    let mut indices = vec![0u32; points.len() * k];
    let mut distances = vec![0f32; points.len() * k];
    // Each chunk's queries are listed only as its turn comes: 8 bytes a point otherwise.
    let every_chunk = |chunk: usize| (chunk * CHUNK..((chunk + 1) * CHUNK).min(points.len())).collect();
    let chunks = points.len().div_ceil(CHUNK);
    let unsettled: Vec<Vec<usize>> = match &grid {
        Some(grid) => {
            let mut rows = (&mut indices, &mut distances);
            let near = (0..chunks).into_par_iter().map(every_chunk);
            let left = settle_from_grid(grid, (points, k), &mut rows, (near, Blocks::near));
            let count: usize = left.iter().map(Vec::len).sum();
            if count > 0 && count * FEW_LEFT <= points.len() {
                settle_from_grid(grid, (points, k), &mut rows, (left.into_par_iter(), Blocks::far))
            } else {
                left
            }
        }
        None => (0..chunks).map(every_chunk).collect(),
    };
    if unsettled.iter().any(|left| !left.is_empty()) {
        fill_from_tree(points, k, (&mut indices, &mut distances), &unsettled);
    }
    Neighbors { k, indices, distances }
}

/// Fills the rows of the points `queries[c]` of each chunk `c` that the grid settles with
/// `blocks`, and returns the others of each chunk, ascending.
fn settle_from_grid(
    grid: &CellGrid,
    (points, k): (&[Vec3], usize),
    (indices, distances): &mut (&mut Vec<u32>, &mut Vec<f32>),
    (queries, blocks): (impl IndexedParallelIterator<Item = Vec<usize>>, fn() -> Blocks),
) -> Vec<Vec<usize>> {
    indices
        .par_chunks_mut(CHUNK * k)
        .zip(distances.par_chunks_mut(CHUNK * k))
        .zip(queries)
        .enumerate()
        .map(|(chunk, (rows, queries))| {
            settle_chunk(grid, (points, k), chunk * CHUNK, rows, (queries, blocks()))
        })
        .collect()
}

/// Fills the rows (`index_rows`, `distance_rows`) of the points from `first` on that the
/// grid settles among `queries`, and returns the others, ascending.
fn settle_chunk(
    grid: &CellGrid,
    (points, k): (&[Vec3], usize),
    first: usize,
    (index_rows, distance_rows): (&mut [u32], &mut [f32]),
    (queries, mut blocks): (Vec<usize>, Blocks),
) -> Vec<usize> {
    let (mut nearest, mut left) = (Vec::new(), Vec::new());
    let mut previous: Option<(Vec3, f32)> = None;
    for i in grid.cell_by_cell(&queries) {
        let rows = (i - first) * k..(i - first + 1) * k;
        let within =
            previous.map(|(point, reach)| ((reach + point.distance(points[i])) * BOUND_SLACK).powi(2));
        previous = None;
        if grid.nearest((i, k + 1), within, &mut blocks, &mut nearest) {
            write_row(&nearest, i as u32, &mut index_rows[rows.clone()], &mut distance_rows[rows.clone()]);
            previous = Some((points[i], distance_rows[rows.end - 1]));
        } else {
            left.push(i);
        }
    }
    left.sort_unstable();
    left
}

/// Fills the rows `unsettled[c]` of each chunk `c` from a k-d tree of `points`.
fn fill_from_tree(
    points: &[Vec3],
    k: usize,
    (indices, distances): (&mut [u32], &mut [f32]),
    unsettled: &[Vec<usize>],
) {
    let entries: Vec<[f32; 3]> = points.par_iter().map(|p| p.to_array()).collect();
    let tree: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&entries)
        .unwrap_or_else(|e| unreachable!("point indices fit u32 by contract: {e}"));
    indices
        .par_chunks_mut(CHUNK * k)
        .zip(distances.par_chunks_mut(CHUNK * k))
        .zip(unsettled)
        .enumerate()
        .for_each(|(chunk, ((index_rows, distance_rows), left))| {
            let mut previous: Option<(Vec3, f32)> = None;
            for &i in left {
                let offset = i - chunk * CHUNK;
                let row = &mut index_rows[offset * k..(offset + 1) * k];
                let row_distances = &mut distance_rows[offset * k..(offset + 1) * k];
                let bound = previous.map(|(point, reach)| reach + point.distance(points[i]));
                let reach = fill_row(&tree, &entries[i], i as u32, bound, row, row_distances);
                previous = Some((points[i], reach));
            }
        });
}

/// Queries `k + 1` points and writes all but `self_index` (`write_row`), equally distant
/// ones in index order; returns the distance to the farthest of them.
///
/// `bound`, when given, is a distance within which `k + 1` points are known to lie (an
/// earlier query's reach plus the step to this one, by the triangle inequality): it prunes
/// the search without changing its answer.
fn fill_row(
    tree: &ImmutableKdTree<f32, 3>,
    query: &[f32; 3],
    self_index: u32,
    bound: Option<f32>,
    row: &mut [u32],
    row_distances: &mut [f32],
) -> f32 {
    let k = row.len();
    let wanted = NonZeroUsize::new(k + 1).unwrap_or(NonZeroUsize::MIN);
    let unbounded = || tree.query(query).nearest_n::<SquaredEuclidean<f32>>(wanted).execute();
    let found = match bound {
        Some(reach) => {
            let radius = (reach * BOUND_SLACK).powi(2);
            let found = tree.query(query).nearest_n::<SquaredEuclidean<f32>>(wanted).within(radius).execute();
            if found.len() == wanted.get() { found } else { unbounded() }
        }
        None => unbounded(),
    };
    let farthest = found.last().map_or(0.0, |hit| hit.distance);
    // Every point as near as the farthest found, so that ties there go by index too.
    let tied = tree.query(query).within::<SquaredEuclidean<f32>>(farthest * BOUND_SLACK.powi(2)).execute();
    let mut keys: Vec<u64> = tied.iter().map(|hit| neighbour_key(hit.distance, hit.item)).collect();
    keys.sort_unstable();
    keys.truncate(k + 1);
    write_row(&keys, self_index, row, row_distances);
    farthest.sqrt()
}

/// Writes the first `row.len()` of `nearest` (`neighbour_key`s, nearest first) other than
/// `self_index`: dropping by index, not by position, matters when duplicates tie with the
/// query point at distance 0. A short row repeats its farthest neighbour.
fn write_row(nearest: &[u64], self_index: u32, row: &mut [u32], row_distances: &mut [f32]) {
    let mut others = nearest.iter().map(|&key| neighbour_of(key)).filter(|&(_, index)| index != self_index);
    let mut last = (self_index, 0.0);
    for (slot, slot_distance) in row.iter_mut().zip(row_distances.iter_mut()) {
        if let Some((squared, index)) = others.next() {
            last = (index, squared.sqrt());
        }
        (*slot, *slot_distance) = last;
    }
}

/// A neighbour as one integer that orders by squared distance, then by index, so that
/// neighbours sort as plain integers: the bits of a non-negative float order as the float does.
pub(crate) fn neighbour_key(squared: f32, index: u32) -> u64 {
    (u64::from(squared.to_bits()) << 32) | u64::from(index)
}

/// The squared distance and index of a `neighbour_key`.
pub(crate) fn neighbour_of(key: u64) -> (f32, u32) {
    (f32::from_bits((key >> 32) as u32), key as u32)
}

/// Widens a bound against rounding, so that a point exactly at it is never lost.
const BOUND_SLACK: f32 = 1.0 + 1e-4;
