//! The k-nearest-neighbour table (METHOD.md §2.1), shared by normals, orientation and the fit.

use std::num::NonZeroUsize;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

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

/// The `k` nearest neighbours of every point, in parallel.
///
/// Callers guarantee `points.len() > k` and fewer than `u32::MAX` points. Should a row
/// still come up short, it is padded by repeating its farthest neighbour so the table
/// keeps its shape. Coincident points are neighbours of each other at distance 0.
pub fn k_nearest(points: &[Vec3], k: usize) -> Neighbors {
    if k == 0 || points.is_empty() {
        return Neighbors { k, ..Neighbors::default() };
    }
    let entries: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    let tree: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&entries)
        .unwrap_or_else(|e| unreachable!("point indices fit u32 by contract: {e}"));
    let mut indices = vec![0u32; points.len() * k];
    let mut distances = vec![0f32; points.len() * k];
    indices.par_chunks_mut(CHUNK * k).zip(distances.par_chunks_mut(CHUNK * k)).enumerate().for_each(
        |(chunk, (index_rows, distance_rows))| {
            let first = chunk * CHUNK;
            let rows = index_rows.chunks_mut(k).zip(distance_rows.chunks_mut(k));
            let mut previous: Option<(Vec3, f32)> = None;
            for (offset, (row, row_distances)) in rows.enumerate() {
                let i = first + offset;
                let bound = previous.map(|(point, reach)| reach + point.distance(points[i]));
                let reach = fill_row(&tree, &entries[i], i as u32, bound, row, row_distances);
                previous = Some((points[i], reach));
            }
        },
    );
    Neighbors { k, indices, distances }
}

/// Queries `k + 1` points and drops `self_index`; returns the distance to the farthest of
/// them. Dropping by index, not by position, matters when duplicates tie with the query
/// point at distance 0.
///
/// `bound`, when given, is a distance within which `k + 1` points are known to lie (the
/// previous query's reach plus the step to this one, by the triangle inequality): it prunes
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
    let mut others = found.iter().filter(|hit| hit.item != self_index).take(k);
    let mut last = (self_index, 0.0);
    for (slot, slot_distance) in row.iter_mut().zip(row_distances.iter_mut()) {
        if let Some(hit) = others.next() {
            last = (hit.item, hit.distance.sqrt());
        }
        (*slot, *slot_distance) = last;
    }
    found.last().map_or(0.0, |hit| hit.distance.sqrt())
}

/// Widens a bound against rounding, so that a point exactly at it is never lost.
const BOUND_SLACK: f32 = 1.0 + 1e-4;
