//! Coincident and near-coincident points, which scans contain, would give zero support
//! radii and NaN frames downstream; they are merged before the neighbour search.
//!
//! How near is near follows the f32 resolution at the points' own coordinates, never the
//! cloud's extent: one stray point far off must not turn a whole surface into duplicates.

use std::collections::HashMap;

use glam::{DVec3, IVec3, Vec3};
use rayon::prelude::*;

use crate::duplicate_clusters::Clusters;

/// The points that survive merging, as indices into the input, in input order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DuplicateMerge {
    pub kept: Vec<u32>,
    pub merged_count: usize,
}

/// Coarse cells are this many fine cells wide: a point farther than a fine cell from its
/// coarse cell's faces and alone in that cell has no duplicate, which settles almost all
/// points with one parallel sort.
const COARSE_CELLS_PER_TOLERANCE: f32 = 64.0;

/// Greedy merge in input order: a point is dropped when it merges with a point kept before
/// it (`merge_as_duplicates`: within `ulps` f32 steps at its own coordinates), so no two kept
/// points merge and each dropped point merges with an earlier kept one. An `ulps` of zero (or
/// a non-finite one) merges exact duplicates only.
pub fn merge_duplicates(points: &[Vec3], ulps: f32) -> DuplicateMerge {
    let grid = Grid::over(points, ulps);
    let candidates = possible_duplicates(points, &grid);
    let dropped = greedy_merge(points, &grid, &candidates);
    let kept: Vec<u32> = (0..points.len() as u32).filter(|&i| !dropped[i as usize]).collect();
    DuplicateMerge { merged_count: points.len() - kept.len(), kept }
}

/// Whether `a` and `b` merge: when they lie within `ulps` f32 steps at the largest magnitude
/// of their coordinates, the resolution f32 gives a point there. So points far out, where
/// f32 is coarse, merge more readily than points near the origin, and one of them merges
/// nothing near the origin.
pub fn merge_as_duplicates(a: Vec3, b: Vec3, ulps: f32) -> bool {
    let tolerance = largest_merge_distance(a.abs().max(b.abs()).max_element(), ulps);
    a.distance_squared(b) <= tolerance * tolerance
}

/// The farthest apart two points whose coordinates are at most `magnitude` in size can lie and
/// still merge.
pub fn largest_merge_distance(magnitude: f32, ulps: f32) -> f32 {
    ulps * f32_step(magnitude)
}

/// The step from `magnitude` (at least 0) to the next f32 up.
fn f32_step(magnitude: f32) -> f32 {
    magnitude.next_up() - magnitude
}

/// Cells over the cloud's finite bounding box, at least as wide as any pair's tolerance. Cell
/// coordinates are worked out in f64: cells a few f32 steps wide can number 2^24 along an
/// axis, past where f32 arithmetic tells cells apart.
struct Grid {
    origin: DVec3,
    /// The fine cells' width; zero to merge exact duplicates only.
    cell: f64,
    ulps: f32,
}

/// Cells are at least this fraction of the bounding-box diagonal wide, so that cell
/// coordinates fit 32 bits whatever `ulps` is.
const MIN_RELATIVE_CELL: f64 = 1.0 / (1u32 << 28) as f64;

impl Grid {
    fn over(points: &[Vec3], ulps: f32) -> Self {
        let finite = || points.par_iter().copied().filter(|p| p.is_finite());
        let min = finite().reduce(|| Vec3::INFINITY, Vec3::min);
        let max = finite().reduce(|| Vec3::NEG_INFINITY, Vec3::max);
        if !(min.is_finite() && ulps.is_finite() && ulps > 0.0) {
            return Self { origin: DVec3::ZERO, cell: 0.0, ulps: 0.0 };
        }
        let largest = f64::from(largest_merge_distance(min.abs().max(max.abs()).max_element(), ulps));
        let (min, max) = (min.as_dvec3(), max.as_dvec3());
        Self { origin: min, cell: largest.max(min.distance(max) * MIN_RELATIVE_CELL), ulps }
    }

    /// With zero tolerance the "cell" is the exact position, so only equal points meet.
    fn coarse_key(&self, p: Vec3) -> [u32; 3] {
        if self.cell == 0.0 {
            return (p + Vec3::ZERO).to_array().map(f32::to_bits); // + 0 folds -0 into 0
        }
        let cell = self.coarse_position(p).floor();
        cell.to_array().map(|c| c as u32)
    }

    fn coarse_position(&self, p: Vec3) -> DVec3 {
        (p.as_dvec3() - self.origin) / (self.cell * f64::from(COARSE_CELLS_PER_TOLERANCE))
    }

    /// Whether a point within a fine cell of `p` could lie in another coarse cell.
    fn near_coarse_face(&self, p: Vec3) -> bool {
        if self.cell == 0.0 {
            return false;
        }
        let fraction = self.coarse_position(p).fract_gl();
        let margin = 1.0 / f64::from(COARSE_CELLS_PER_TOLERANCE);
        fraction.cmplt(DVec3::splat(margin)).any() || fraction.cmpgt(DVec3::splat(1.0 - margin)).any()
    }

    /// Fine cells are as wide as the largest tolerance: a point's duplicates lie in its 27
    /// neighbours.
    fn fine_cell(&self, p: Vec3) -> IVec3 {
        if self.cell == 0.0 {
            return IVec3::from_array(self.coarse_key(p).map(|b| b as i32));
        }
        ((p.as_dvec3() - self.origin) / self.cell).floor().as_ivec3()
    }

    fn is_duplicate(&self, a: Vec3, b: Vec3) -> bool {
        if self.cell == 0.0 { a + Vec3::ZERO == b + Vec3::ZERO } else { merge_as_duplicates(a, b, self.ulps) }
    }
}

/// The points that might have a duplicate: those sharing a coarse cell, and those near a
/// coarse cell's face. Every other point is certainly unique.
fn possible_duplicates(points: &[Vec3], grid: &Grid) -> Vec<u32> {
    let mut keyed: Vec<([u32; 3], u32)> =
        points.par_iter().enumerate().map(|(i, &p)| (grid.coarse_key(p), i as u32)).collect();
    keyed.par_sort_unstable();
    keyed
        .par_iter()
        .enumerate()
        .filter(|&(position, &(key, i))| {
            let shares_cell = |other: Option<&([u32; 3], u32)>| other.is_some_and(|o| o.0 == key);
            shares_cell(position.checked_sub(1).map(|p| &keyed[p]))
                || shares_cell(keyed.get(position + 1))
                || grid.near_coarse_face(points[i as usize])
        })
        .map(|(_, &(_, i))| i)
        .collect()
}

/// The greedy merge over the candidates, one cluster of touching fine cells at a time (in
/// parallel): a point only ever meets points of its own cluster, so each cluster's greedy
/// pass gives what one pass over all candidates in input order gives. Returns which points
/// were dropped.
fn greedy_merge(points: &[Vec3], grid: &Grid, candidates: &[u32]) -> Vec<bool> {
    let keyed = candidates.par_iter().map(|&i| (grid.fine_cell(points[i as usize]).to_array(), i)).collect();
    let clusters = Clusters::of(keyed, grid.cell > 0.0);
    let dropped_points: Vec<u32> =
        clusters.par_iter().flat_map_iter(|members| greedy_in_order(points, grid, members)).collect();
    let mut dropped = vec![false; points.len()];
    for i in dropped_points {
        dropped[i as usize] = true;
    }
    dropped
}

/// The sequential greedy pass over `members` (in input order); returns the dropped ones.
fn greedy_in_order(points: &[Vec3], grid: &Grid, members: &[u32]) -> Vec<u32> {
    let mut kept_by_cell: HashMap<IVec3, Vec<u32>> = HashMap::new();
    let mut dropped = Vec::new();
    for &i in members {
        let p = points[i as usize];
        let cell = grid.fine_cell(p);
        if has_kept_duplicate(points, grid, &kept_by_cell, cell, p) {
            dropped.push(i);
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
    let reach = if grid.cell == 0.0 { 0 } else { 1 };
    (-reach..=reach)
        .flat_map(|dz| {
            (-reach..=reach).flat_map(move |dy| (-reach..=reach).map(move |dx| IVec3::new(dx, dy, dz)))
        })
        .filter_map(|offset| kept_by_cell.get(&(cell + offset)))
        .flatten()
        .any(|&k| grid.is_duplicate(points[k as usize], p))
}

#[cfg(test)]
mod tests {
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// The ulps that make `tolerance` the merge distance between points in [1, 2), where an
    /// ulp is `f32::EPSILON`.
    fn ulps_at_one(tolerance: f32) -> f32 {
        tolerance / f32::EPSILON
    }

    /// The merge as it was before clusters: one sequential greedy pass over every candidate
    /// in input order.
    fn merge_in_one_pass(points: &[Vec3], ulps: f32) -> DuplicateMerge {
        let grid = Grid::over(points, ulps);
        let mut candidates = possible_duplicates(points, &grid);
        candidates.sort_unstable();
        let mut dropped = vec![false; points.len()];
        for i in greedy_in_order(points, &grid, &candidates) {
            dropped[i as usize] = true;
        }
        let kept: Vec<u32> = (0..points.len() as u32).filter(|&i| !dropped[i as usize]).collect();
        DuplicateMerge { merged_count: points.len() - kept.len(), kept }
    }

    /// The definition, point against point.
    fn merge_by_brute_force(points: &[Vec3], ulps: f32) -> Vec<u32> {
        let mut kept: Vec<u32> = Vec::new();
        for (i, &p) in points.iter().enumerate() {
            if !kept.iter().any(|&k| merge_as_duplicates(points[k as usize], p, ulps)) {
                kept.push(i as u32);
            }
        }
        kept
    }

    fn random_direction(rng: &mut ChaCha8Rng) -> Vec3 {
        loop {
            let v = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::ONE;
            if let Some(unit) = v.try_normalize().filter(|_| v.length() <= 1.0) {
                return unit;
            }
        }
    }

    /// Random points in the box [1, 2)^3 with planted duplicates of every kind, shuffled: exact
    /// copies, copies moved by up to 1.5 tolerances (so some are not duplicates), chains
    /// with links shorter than the tolerance (greedy keeps every other link) and dense
    /// blobs of a few tolerances.
    fn cloud_with_planted_duplicates(seed: u64, count: usize, tolerance: f32) -> Vec<Vec3> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut points: Vec<Vec3> =
            (0..count).map(|_| Vec3::ONE + Vec3::new(rng.random(), rng.random(), rng.random())).collect();
        for _ in 0..count / 10 {
            let original = points[rng.random_range(0..count)];
            let moved = random_direction(&mut rng) * rng.random_range(0.0..1.5) * tolerance;
            points.push(if rng.random_bool(0.3) { original } else { original + moved });
        }
        for _ in 0..count / 200 {
            let mut link = points[rng.random_range(0..count)];
            for _ in 0..rng.random_range(2..30) {
                link += random_direction(&mut rng) * rng.random_range(0.6..0.99) * tolerance;
                points.push(link);
            }
        }
        for _ in 0..3 {
            let centre = points[rng.random_range(0..count)];
            points.extend(
                (0..300)
                    .map(|_| centre + random_direction(&mut rng) * rng.random_range(0.0..3.0) * tolerance),
            );
        }
        for i in (1..points.len()).rev() {
            points.swap(i, rng.random_range(0..=i));
        }
        points
    }

    #[test]
    fn clusters_merge_what_one_pass_merges_on_random_clouds() {
        for seed in 0..6 {
            let tolerance = [1e-3, 4e-3, 2e-2][seed as usize % 3];
            let points = cloud_with_planted_duplicates(seed, 20_000, tolerance);
            let merge = merge_duplicates(&points, ulps_at_one(tolerance));
            assert_eq!(merge, merge_in_one_pass(&points, ulps_at_one(tolerance)), "seed {seed}");
            assert!(merge.merged_count > 2_000, "seed {seed}: only {} merged", merge.merged_count);
        }
    }

    #[test]
    fn clusters_merge_what_one_pass_merges_with_zero_tolerance() {
        let mut points = cloud_with_planted_duplicates(7, 20_000, 1e-3);
        points.extend_from_within(..500);
        points.push(-Vec3::ZERO);
        points.push(Vec3::ZERO);
        let merge = merge_duplicates(&points, 0.0);
        assert_eq!(merge, merge_in_one_pass(&points, 0.0));
        assert!(merge.merged_count > 500);
    }

    #[test]
    fn clusters_merge_what_one_pass_merges_on_coarse_cell_faces() {
        // A lattice whose points sit exactly on coarse-cell faces, with near copies across them;
        // in [16, 32), where an ulp is 16 epsilons.
        let ulps = 1.0 / COARSE_CELLS_PER_TOLERANCE / (16.0 * f32::EPSILON);
        let mut points: Vec<Vec3> = (0..4096)
            .map(|i| Vec3::splat(16.0) + Vec3::new((i % 16) as f32, ((i / 16) % 16) as f32, (i / 256) as f32))
            .collect();
        let shifts = [
            Vec3::new(-0.012, 0.0, 0.0),
            Vec3::new(0.006, -0.009, 0.004),
            Vec3::new(0.011, 0.0, -0.011),
            Vec3::splat(0.02),
        ];
        for (i, shift) in shifts.iter().cycle().take(4000).enumerate() {
            points.push(points[i * 7 % 4096] + *shift);
        }
        let merge = merge_duplicates(&points, ulps);
        assert_eq!(merge, merge_in_one_pass(&points, ulps));
        assert!(merge.merged_count > 1000);
    }

    #[test]
    fn merge_is_the_greedy_definition_on_small_clouds() {
        for seed in 10..14 {
            let points = cloud_with_planted_duplicates(seed, 1_500, 1e-2);
            let merge = merge_duplicates(&points, ulps_at_one(1e-2));
            assert_eq!(merge.kept, merge_by_brute_force(&points, ulps_at_one(1e-2)), "seed {seed}");
        }
    }

    #[test]
    fn a_far_stray_point_leaves_the_spacing_of_the_rest_alone() {
        // A 100 x 100 sheet a thousandth apart, near the origin, and one point 1e4 away.
        let mut points: Vec<Vec3> =
            (0..10_000).map(|i| Vec3::new((i % 100) as f32, (i / 100) as f32, 0.0) * 1e-3).collect();
        points.push(Vec3::new(1e4, 0.0, 0.0));
        assert_eq!(merge_duplicates(&points, 4.0).merged_count, 0);
        points.extend_from_within(..100);
        assert_eq!(merge_duplicates(&points, 4.0).merged_count, 100, "exact copies still merge");
    }

    #[test]
    fn a_pair_merges_within_the_f32_steps_at_its_coordinates() {
        let far = Vec3::new(4096.0, 1.0, 0.0);
        assert!(merge_as_duplicates(far, far + Vec3::new(0.0, 4e-4, 0.0), 1.0), "a step is 4.9e-4 there");
        assert!(!merge_as_duplicates(far, far + Vec3::new(0.0, 6e-4, 0.0), 1.0));
        let near = Vec3::new(1.0, 0.5, 0.0);
        assert!(!merge_as_duplicates(near, near + Vec3::new(0.0, 4e-4, 0.0), 1.0), "but 1.2e-7 at 1");
        assert_eq!(largest_merge_distance(1.0, 2.0), 2.0 * f32::EPSILON);
        assert_eq!(largest_merge_distance(0.0, 1.0), f32::from_bits(1), "the least step, at zero");
    }
}
