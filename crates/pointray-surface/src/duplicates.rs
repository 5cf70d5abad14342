//! Coincident and near-coincident points, which scans contain, would give zero support
//! radii and NaN frames downstream; they are merged before the neighbour search.

use std::collections::HashMap;

use glam::{IVec3, Vec3};
use rayon::prelude::*;

/// The points that survive merging, as indices into the input, in input order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DuplicateMerge {
    pub kept: Vec<u32>,
    pub merged_count: usize,
}

/// Coarse cells are this many tolerances wide: a point farther than `tolerance` from its
/// coarse cell's faces and alone in that cell has no duplicate, which settles almost all
/// points with one parallel sort.
const COARSE_CELLS_PER_TOLERANCE: f32 = 64.0;

/// Greedy merge in input order: a point is dropped when it lies within `tolerance` of a
/// point kept before it, so kept points are pairwise farther apart than `tolerance` and
/// each dropped point is within `tolerance` of an earlier kept one. A `tolerance` of zero
/// (or a non-finite one) merges exact duplicates only.
pub fn merge_duplicates(points: &[Vec3], tolerance: f32) -> DuplicateMerge {
    let grid = Grid::over(points, tolerance);
    let candidates = possible_duplicates(points, &grid);
    let dropped = greedy_merge(points, &grid, &candidates);
    let kept: Vec<u32> = (0..points.len() as u32).filter(|&i| !dropped[i as usize]).collect();
    DuplicateMerge { merged_count: points.len() - kept.len(), kept }
}

/// Cells over the cloud's finite bounding box.
struct Grid {
    origin: Vec3,
    tolerance: f32,
}

/// Tolerances are raised to this fraction of the bounding-box diagonal, far below f32
/// resolution, so that cell coordinates fit 32 bits.
const MIN_RELATIVE_TOLERANCE: f32 = 1.0 / (1u32 << 28) as f32;

impl Grid {
    fn over(points: &[Vec3], tolerance: f32) -> Self {
        let finite = || points.par_iter().copied().filter(|p| p.is_finite());
        let min = finite().reduce(|| Vec3::INFINITY, Vec3::min);
        let max = finite().reduce(|| Vec3::NEG_INFINITY, Vec3::max);
        if !min.is_finite() {
            return Self { origin: Vec3::ZERO, tolerance: 0.0 };
        }
        let tolerance = if tolerance.is_finite() && tolerance > 0.0 {
            tolerance.max(min.distance(max) * MIN_RELATIVE_TOLERANCE)
        } else {
            0.0
        };
        Self { origin: min, tolerance }
    }

    /// With zero tolerance the "cell" is the exact position, so only equal points meet.
    fn coarse_key(&self, p: Vec3) -> [u32; 3] {
        if self.tolerance == 0.0 {
            return (p + Vec3::ZERO).to_array().map(f32::to_bits); // + 0 folds -0 into 0
        }
        let cell = self.coarse_position(p).floor();
        cell.to_array().map(|c| c as u32)
    }

    fn coarse_position(&self, p: Vec3) -> Vec3 {
        (p - self.origin) / (self.tolerance * COARSE_CELLS_PER_TOLERANCE)
    }

    /// Whether a point within `tolerance` of `p` could lie in another coarse cell.
    fn near_coarse_face(&self, p: Vec3) -> bool {
        if self.tolerance == 0.0 {
            return false;
        }
        let fraction = self.coarse_position(p).fract_gl();
        let margin = 1.0 / COARSE_CELLS_PER_TOLERANCE;
        fraction.cmplt(Vec3::splat(margin)).any() || fraction.cmpgt(Vec3::splat(1.0 - margin)).any()
    }

    /// Fine cells are one tolerance wide: a point's duplicates lie in its 27 neighbours.
    fn fine_cell(&self, p: Vec3) -> IVec3 {
        if self.tolerance == 0.0 {
            return IVec3::from_array(self.coarse_key(p).map(|b| b as i32));
        }
        ((p - self.origin) / self.tolerance).floor().as_ivec3()
    }

    fn is_duplicate(&self, a: Vec3, b: Vec3) -> bool {
        if self.tolerance == 0.0 {
            a + Vec3::ZERO == b + Vec3::ZERO
        } else {
            a.distance_squared(b) <= self.tolerance * self.tolerance
        }
    }
}

/// The points that might have a duplicate, in input order: those sharing a coarse cell,
/// and those near a coarse cell's face. Every other point is certainly unique.
fn possible_duplicates(points: &[Vec3], grid: &Grid) -> Vec<u32> {
    let mut keyed: Vec<([u32; 3], u32)> =
        points.par_iter().enumerate().map(|(i, &p)| (grid.coarse_key(p), i as u32)).collect();
    keyed.par_sort_unstable();
    let mut candidates: Vec<u32> = keyed
        .par_iter()
        .enumerate()
        .filter(|&(position, &(key, i))| {
            let shares_cell = |other: Option<&([u32; 3], u32)>| other.is_some_and(|o| o.0 == key);
            shares_cell(position.checked_sub(1).map(|p| &keyed[p]))
                || shares_cell(keyed.get(position + 1))
                || grid.near_coarse_face(points[i as usize])
        })
        .map(|(_, &(_, i))| i)
        .collect();
    candidates.par_sort_unstable();
    candidates
}

/// The sequential greedy pass over the candidates; returns which points were dropped.
fn greedy_merge(points: &[Vec3], grid: &Grid, candidates: &[u32]) -> Vec<bool> {
    let mut kept_by_cell: HashMap<IVec3, Vec<u32>> = HashMap::new();
    let mut dropped = vec![false; points.len()];
    for &i in candidates {
        let p = points[i as usize];
        let cell = grid.fine_cell(p);
        if has_kept_duplicate(points, grid, &kept_by_cell, cell, p) {
            dropped[i as usize] = true;
        } else {
            kept_by_cell.entry(cell).or_default().push(i);
        }
    }
    dropped
}

fn has_kept_duplicate(
    points: &[Vec3],
    grid: &Grid,
    kept_by_cell: &HashMap<IVec3, Vec<u32>>,
    cell: IVec3,
    p: Vec3,
) -> bool {
    let reach = if grid.tolerance == 0.0 { 0 } else { 1 };
    (-reach..=reach)
        .flat_map(|dz| {
            (-reach..=reach).flat_map(move |dy| (-reach..=reach).map(move |dx| IVec3::new(dx, dy, dz)))
        })
        .filter_map(|offset| kept_by_cell.get(&(cell + offset)))
        .flatten()
        .any(|&k| grid.is_duplicate(points[k as usize], p))
}
