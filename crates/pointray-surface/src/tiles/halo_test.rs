//! Which points lie in a tile's halo: within core point `i`'s `reaches[i]` of it, for some
//! `i`. The test is the same for every point, however the candidates are gathered (all at
//! once from a cloud in memory, or batch by batch from the blocks of a sorted file).
//!
//! Most of a tile's points lie deep inside it, where they reach no point outside (a reach of
//! zero). A candidate outside the cells that the reaching points' boxes meet is dropped
//! before any search (`ReachCells`); the core points are taken in runs along the curve, each
//! with the box its reaches span, and only the runs whose box holds a candidate are searched
//! around.

use std::ops::Range;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use crate::tiles::reach_cells::ReachCells;

/// Consecutive core points whose reaches share one box.
const HALO_RUN_POINTS: usize = 256;

/// Widens each box against rounding: by this share of its reaches, and of its coordinates.
const BOX_SLACK: f32 = 1e-3;
const COORDINATE_SLACK: f32 = 1e-6;

pub(crate) struct HaloTest<'a> {
    core_points: &'a [Vec3],
    reaches: &'a [f32],
    /// The box that holds every point the core points reach.
    bounds: (Vec3, Vec3),
    /// Runs of core points, with the box that holds every point they reach.
    runs: Vec<(Range<usize>, (Vec3, Vec3))>,
    /// The cells the reaching points' boxes meet; none when some reach is unbounded.
    cells: Option<ReachCells>,
}

impl<'a> HaloTest<'a> {
    pub(crate) fn new(core_points: &'a [Vec3], reaches: &'a [f32]) -> Self {
        let runs: Vec<(Range<usize>, (Vec3, Vec3))> = core_points
            .par_chunks(HALO_RUN_POINTS)
            .zip(reaches.par_chunks(HALO_RUN_POINTS))
            .enumerate()
            // A reach of zero reaches no other point.
            .filter(|(_, (_, reaches))| reaches.iter().any(|&reach| reach != 0.0))
            .map(|(run, (points, reaches))| {
                let start = run * HALO_RUN_POINTS;
                (start..start + points.len(), reach_box(points, reaches))
            })
            .collect();
        let bounds = runs
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (_, (a, b))| (lo.min(*a), hi.max(*b)));
        let finite = bounds.0.is_finite() && bounds.1.is_finite();
        // Each point's own box: a run's box may span a jump of the curve.
        let cells = finite.then(|| {
            let boxes: Vec<(Vec3, Vec3)> = runs
                .iter()
                .flat_map(|(run, _)| run.clone())
                .filter(|&i| reaches[i] != 0.0)
                .map(|i| reach_box(&core_points[i..=i], &reaches[i..=i]))
                .collect();
            ReachCells::new(bounds, &boxes)
        });
        Self { core_points, reaches, bounds, runs, cells }
    }

    /// Whether points in the box from `lo` to `hi` may lie within reach of a core point.
    pub(crate) fn may_reach_box(&self, (lo, hi): (Vec3, Vec3)) -> bool {
        let (min, max) = self.bounds;
        !(lo.cmpgt(max).any() || hi.cmplt(min).any()) && self.cells.as_ref().is_none_or(|c| c.meets((lo, hi)))
    }

    /// Whether `point` may lie within reach of a core point.
    pub(crate) fn may_reach(&self, point: Vec3) -> bool {
        let (min, max) = self.bounds;
        point.cmpge(min).all()
            && point.cmple(max).all()
            && self.cells.as_ref().is_none_or(|c| c.contains(point))
    }

    /// The indices of the `candidates` within reach of a core point, ascending. The tree
    /// only narrows the search (with a margin); the distances are compared here, so that
    /// the answer for a point does not depend on the other candidates.
    pub(crate) fn reached(&self, candidates: &[Vec3]) -> Vec<u32> {
        if candidates.is_empty() {
            return Vec::new();
        }
        let entries: Vec<[f32; 3]> = candidates.iter().map(|p| p.to_array()).collect();
        let tree: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&entries)
            .unwrap_or_else(|e| unreachable!("a batch of candidates fits u32 indices: {e}"));
        drop(entries);
        let near_candidates = |(lo, hi): (Vec3, Vec3)| {
            if !(lo.is_finite() && hi.is_finite()) {
                return true;
            }
            let (centre, half_diagonal) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
            let nearest = tree.query(&centre.to_array()).nearest_one::<SquaredEuclidean<f32>>().execute();
            nearest.distance.sqrt() <= half_diagonal * (1.0 + BOX_SLACK)
        };
        let mut reached: Vec<u32> = self
            .runs
            .par_iter()
            .filter(|(_, bounds)| near_candidates(*bounds))
            .flat_map_iter(|(run, _)| run.clone())
            .filter(|&i| self.reaches[i] != 0.0)
            .flat_map_iter(|i| {
                let (p, r) = (self.core_points[i], self.reaches[i]);
                let search = r * r * (1.0 + 1e-4);
                let hits =
                    tree.query(&p.to_array()).within::<SquaredEuclidean<f32>>(search).unsorted().execute();
                hits.into_iter()
                    .map(|hit| hit.item)
                    .filter(move |&j| (candidates[j as usize] - p).length_squared() <= r * r)
            })
            .collect();
        reached.par_sort_unstable();
        reached.dedup();
        reached
    }
}

/// The box that holds every point within `reaches[i]` of `points[i]`, for any `i`, widened
/// against rounding. Points of reach zero reach no other point, and are left out: when all
/// are, the box is empty (infinite `lo`, negative infinite `hi`).
pub(crate) fn reach_box(points: &[Vec3], reaches: &[f32]) -> (Vec3, Vec3) {
    let (lo, hi, widest) = points
        .iter()
        .zip(reaches)
        .filter(|(_, reach)| **reach != 0.0)
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY, 0.0f32), |(lo, hi, widest), (&p, &r)| {
            (lo.min(p - r), hi.max(p + r), widest.max(r))
        });
    if lo.cmpgt(hi).any() {
        return (lo, hi);
    }
    let margin = Vec3::splat(widest * BOX_SLACK) + lo.abs().max(hi.abs()) * COORDINATE_SLACK;
    (lo - margin, hi + margin)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every candidate within reach of a core point, by comparing all pairs.
    fn reached_by_brute_force(core: &[Vec3], reaches: &[f32], candidates: &[Vec3]) -> Vec<u32> {
        (0..candidates.len() as u32)
            .filter(|&j| {
                core.iter()
                    .zip(reaches)
                    .any(|(&p, &r)| (candidates[j as usize] - p).length_squared() <= r * r)
            })
            .collect()
    }

    #[test]
    fn the_halo_is_every_candidate_within_reach_and_no_other() {
        // A core along a curve through a field of candidates, reaches varying by 20 times.
        let core: Vec<Vec3> =
            (0..2000).map(|i| i as f32 * 0.01).map(|t| Vec3::new(t.cos() * 5.0, t.sin() * 5.0, t)).collect();
        let reaches: Vec<f32> = (0..2000).map(|i| 0.01 + 0.2 * ((i * 37 % 101) as f32 / 100.0)).collect();
        let candidates: Vec<Vec3> = (0..20000)
            .map(|i| {
                let t = i as f32 * 0.001;
                Vec3::new((t * 7.0).sin() * 6.0, (t * 3.0).cos() * 6.0, (t * 11.0).sin() * 10.0 + 10.0)
            })
            .collect();
        let test = HaloTest::new(&core, &reaches);
        let kept: Vec<u32> =
            (0..candidates.len() as u32).filter(|&j| test.may_reach(candidates[j as usize])).collect();
        let points: Vec<Vec3> = kept.iter().map(|&j| candidates[j as usize]).collect();
        let reached: Vec<u32> = test.reached(&points).into_iter().map(|j| kept[j as usize]).collect();
        let expected = reached_by_brute_force(&core, &reaches, &candidates);
        assert!(expected.len() > 20, "the field meets the core: {}", expected.len());
        assert!(kept.len() < candidates.len() / 2, "the cells drop most candidates: {} kept", kept.len());
        assert_eq!(reached, expected);
    }

    #[test]
    fn an_unbounded_reach_takes_every_candidate() {
        let core = [Vec3::ZERO, Vec3::X];
        let test = HaloTest::new(&core, &[0.1, f32::INFINITY]);
        assert!(test.may_reach(Vec3::splat(1e6)));
        assert_eq!(test.reached(&[Vec3::splat(1e6), Vec3::splat(-3.0)]), vec![0, 1]);
    }
}
