//! How far a tile's halo reaches: it holds each tile point's neighbourhood, so that every
//! patch of the tile that depends only on its neighbourhood (position, fit, support, colour,
//! a normal from the input or toward a sensor) is the one a single pass makes. Each point
//! reaches as far as an upper bound on its neighbourhood radius: any upper bound keeps that
//! equality, and a loose one only adds halo points. The bound comes from the points' order
//! along the Morton curve, in linear time, and from a k-d tree only where the curve jumps.
//! Both look past the tile's ends along the curve, where a few points cut off by the curve
//! have their neighbours. Prep merges duplicates before it looks for neighbours, so only
//! neighbours that stand for distinct points of the merged cloud are counted
//! (`DistinctNeighbours`).
//!
//! The halo does not hold its own points' neighbourhoods in turn. Those points' normals serve
//! only to orient the tile's normals over the neighbour graph, where a tile's sign may differ
//! from a single pass's anyway; reaching twice as far for them made every halo twice as deep,
//! and around an isolated point, whose neighbours lie far off on a dense surface, it pulled a
//! wide ball of that surface into the halo.

use std::num::NonZeroUsize;
use std::ops::Range;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use pointray_patches::PrepSettings;
use rayon::prelude::*;

use crate::neighbors::{neighbour_key, neighbour_of};
use crate::tiles::curve_span::CurveSpan;
use crate::tiles::halo_test::reach_box;

/// The points on either side of a point along the curve among which its neighbourhood is
/// bounded.
const CURVE_WINDOW: usize = 32;

/// A bound more than this many times the median bound of the points around it along the
/// curve is taken to come from a jump of the curve, and is found exactly instead. Measured on
/// 3M points sampled on the dragon in 14 tiles (with reaches of twice the bound), halos then
/// held 1.1-1.3 times the points that exact radii give, where the window's bounds alone gave
/// 1.5-18 times.
const LOOSE_BOUND: f32 = 1.5;

/// The points on either side whose bounds give the median.
const MEDIAN_SPAN: usize = 16;

/// The points past each end of a tile along the curve that its reaches look at.
pub(crate) const CURVE_CONTEXT: usize = CURVE_WINDOW;

/// The exact bound asks the k-d tree for this many times `k` points, so that duplicates among
/// them still leave `k` distinct ones.
const EXACT_CANDIDATES_PER_NEIGHBOUR: usize = 4;

/// The points on either side of a point along the curve of the quick bound that keeps a
/// run of tile points inside its tile.
const QUICK_WINDOW: usize = 8;

/// Consecutive tile points whose quick bounds are tested against the tile's faces together.
/// Measured on 10M points sampled on the dragon in 9 tiles, runs of 256 left 33-44% of the
/// points to be bounded closely, runs of 32 14-20%. Runs longer than `MEDIAN_SPAN` keep most
/// medians clear of the zeros of the runs beside them (a median pulled low only sends more
/// points to the tree).
const GATE_RUN_POINTS: usize = 32;

/// How far the halo reaches around each point of `curve[core]`. `curve` holds a stretch of
/// the cloud in Morton order: the tile's points (`core`) and up to `CURVE_CONTEXT` points on
/// either side of them. Prep merges points within `duplicate_distance` of each other.
///
/// Given the tile's `span` of the curve, the runs of `GATE_RUN_POINTS` tile points that a
/// quick bound keeps inside it reach no other tile's point whatever their bounds, and get
/// reaches of zero: most of a tile's points lie deep inside it.
pub(crate) fn halo_reaches(
    curve: &[Vec3],
    core: Range<usize>,
    settings: &PrepSettings,
    (duplicate_distance, span): (f32, Option<&CurveSpan>),
) -> Vec<f32> {
    let distinct = DistinctNeighbours::new(neighbourhood_size(settings), duplicate_distance);
    let near_faces = match span {
        Some(span) => runs_near_faces(curve, core.clone(), &distinct, span),
        None => vec![true; core.len().div_ceil(GATE_RUN_POINTS)],
    };
    neighbourhood_bounds(curve, core, &distinct, &near_faces)
}

/// Whether each run of `GATE_RUN_POINTS` points of `points[core]` may reach past `span`, by
/// bounds from `QUICK_WINDOW` points on either side.
fn runs_near_faces(
    points: &[Vec3],
    core: Range<usize>,
    distinct: &DistinctNeighbours,
    span: &CurveSpan,
) -> Vec<bool> {
    let everywhere = vec![true; core.len().div_ceil(GATE_RUN_POINTS)];
    let quick = curve_window_radii(points, core.clone(), distinct, (QUICK_WINDOW, &everywhere));
    points[core]
        .par_chunks(GATE_RUN_POINTS)
        .zip(quick.par_chunks(GATE_RUN_POINTS))
        .map(|(run, reaches)| !span.holds(reach_box(run, reaches)))
        .collect()
}

/// Counts neighbours as the merged cloud has them. Prep keeps a point only when no point kept
/// before it lies within the duplicate distance, and each point it drops lies within that
/// distance of a kept one. So neighbours at least twice the duplicate distance from the point
/// and from each other stand for distinct kept points other than the point, each within the
/// duplicate distance of its stand-in.
struct DistinctNeighbours {
    k: usize,
    duplicate_distance: f32,
    separation_squared: f32,
}

impl DistinctNeighbours {
    fn new(k: usize, duplicate_distance: f32) -> Self {
        let separation = 2.0 * duplicate_distance;
        Self { k, duplicate_distance, separation_squared: separation * separation }
    }

    /// An upper bound on the distance from `point` to its `k`-th nearest neighbour in the
    /// merged cloud, from the raw points `candidates` (`neighbour_key`s of points of
    /// `points`, in any order; reordered here): unbounded when they hold fewer than `k`
    /// distinct neighbours.
    fn bound(
        &self,
        point: Vec3,
        points: &[Vec3],
        candidates: &mut [u64],
        picked: &mut Vec<(f32, Vec3)>,
    ) -> f32 {
        picked.clear();
        // Most rows hold no duplicate: their k nearest, sorted, are all it takes.
        let nearest = self.k.min(candidates.len());
        if nearest < candidates.len() {
            candidates.select_nth_unstable(nearest);
        }
        let (first, rest) = candidates.split_at_mut(nearest);
        for part in [first, rest] {
            part.sort_unstable();
            for &key in part.iter() {
                let (squared, index) = neighbour_of(key);
                let candidate = points[index as usize];
                if self.stands_apart(point, squared, candidate, picked) {
                    picked.push((squared.sqrt(), candidate));
                    if picked.len() == self.k {
                        return squared.sqrt() + self.duplicate_distance;
                    }
                }
            }
        }
        f32::INFINITY
    }

    /// Whether `candidate` (at squared distance `squared` from `point`) lies at least the
    /// separation from `point` and from every point `picked` (nearer ones, with their
    /// distances). Only picked points whose distance is within the separation of the
    /// candidate's can lie that near it.
    fn stands_apart(&self, point: Vec3, squared: f32, candidate: Vec3, picked: &[(f32, Vec3)]) -> bool {
        let apart = |other: Vec3| (candidate - other).length_squared() > self.separation_squared;
        let reach = squared.sqrt() - self.separation_squared.sqrt();
        apart(point)
            && picked
                .iter()
                .rev()
                .take_while(|(distance, _)| *distance >= reach)
                .all(|&(_, other)| apart(other))
    }
}

/// The most neighbours any stage of prep takes.
fn neighbourhood_size(settings: &PrepSettings) -> usize {
    settings.k.max(settings.normal_k) as usize
}

/// For each point of `points[core]`, an upper bound on the distance to its `k`-th nearest
/// neighbour in any merged cloud that holds `points`. Unbounded for too few points.
fn neighbourhood_bounds(
    points: &[Vec3],
    core: Range<usize>,
    distinct: &DistinctNeighbours,
    near_faces: &[bool],
) -> Vec<f32> {
    if points.len() <= distinct.k || distinct.k == 0 {
        return vec![f32::INFINITY; core.len()];
    }
    let mut bounds = curve_window_radii(points, core.clone(), distinct, (CURVE_WINDOW, near_faces));
    let loose: Vec<usize> = (0..bounds.len())
        .into_par_iter()
        .filter(|&i| near_faces[i / GATE_RUN_POINTS])
        .map_init(Vec::new, |around, i| stands_out(&bounds, i, around).then_some(i))
        .flatten()
        .collect();
    let queries: Vec<usize> = loose.iter().map(|&i| core.start + i).collect();
    let known: Vec<f32> = loose.iter().map(|&i| bounds[i]).collect();
    let exact = exact_radii(points, &queries, &known, distinct);
    for (i, radius) in loose.iter().zip(exact) {
        // Both bound the radius; the tree's may find too few distinct neighbours.
        bounds[*i] = bounds[*i].min(radius);
    }
    bounds
}

/// The bound for each point of `points[core]` from the `half_width` points on either side of
/// it (the `k`-th nearest of a subset lies no nearer than the `k`-th nearest of all), in the
/// runs of `GATE_RUN_POINTS` that `wanted` marks; zero in the others.
fn curve_window_radii(
    points: &[Vec3],
    core: Range<usize>,
    distinct: &DistinctNeighbours,
    (half_width, wanted): (usize, &[bool]),
) -> Vec<f32> {
    let start = core.start;
    core.into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(candidates, picked), i| {
                if !wanted[(i - start) / GATE_RUN_POINTS] {
                    return 0.0;
                }
                let window = i.saturating_sub(half_width)..(i + half_width + 1).min(points.len());
                let point = points[i];
                candidates.clear();
                candidates.extend(
                    window
                        .filter(|&j| j != i)
                        .map(|j| neighbour_key((points[j] - point).length_squared(), j as u32)),
                );
                distinct.bound(point, points, candidates, picked)
            },
        )
        .collect()
}

/// Whether bound `i` is unbounded or more than `LOOSE_BOUND` times the median of the bounds
/// around it (gathered into `around`, a buffer kept between calls).
fn stands_out(bounds: &[f32], i: usize, around: &mut Vec<f32>) -> bool {
    around.clear();
    around.extend_from_slice(&bounds[i.saturating_sub(MEDIAN_SPAN)..(i + MEDIAN_SPAN + 1).min(bounds.len())]);
    let middle = around.len() / 2;
    let (_, median, _) = around.select_nth_unstable_by(middle, f32::total_cmp);
    !bounds[i].is_finite() || bounds[i] > LOOSE_BOUND * *median
}

/// The bound for each point of `points` named in `queries`, from its nearest points.
/// `known[q]` bounds query `q`'s radius already: the tree is first asked for the `k + 1`
/// nearest within it (enough where no duplicates lie among them, as almost everywhere),
/// and for `EXACT_CANDIDATES_PER_NEIGHBOUR` times as many only where those fall short.
fn exact_radii(points: &[Vec3], queries: &[usize], known: &[f32], distinct: &DistinctNeighbours) -> Vec<f32> {
    if queries.is_empty() {
        return Vec::new();
    }
    let entries: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    let tree: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&entries)
        .unwrap_or_else(|e| unreachable!("a tile's points fit u32 indices: {e}"));
    let few = NonZeroUsize::new(distinct.k + 1).unwrap_or(NonZeroUsize::MIN);
    let many =
        NonZeroUsize::new(EXACT_CANDIDATES_PER_NEIGHBOUR * distinct.k + 1).unwrap_or(NonZeroUsize::MIN);
    queries
        .par_iter()
        .zip(known)
        .map_init(
            || (Vec::new(), Vec::new()),
            |(candidates, picked), (&i, &known)| {
                let query = tree.query(&entries[i]);
                let nearby = query.nearest_n::<SquaredEuclidean<f32>>(few).within(known * known).execute();
                candidates.clear();
                candidates.extend(nearby.iter().map(|hit| neighbour_key(hit.distance, hit.item)));
                let bound = distinct.bound(points[i], points, candidates, picked);
                if bound.is_finite() {
                    return bound;
                }
                let found = tree.query(&entries[i]).nearest_n::<SquaredEuclidean<f32>>(many).execute();
                candidates.clear();
                candidates.extend(found.iter().map(|hit| neighbour_key(hit.distance, hit.item)));
                distinct.bound(points[i], points, candidates, picked)
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::morton::morton_order;
    use crate::neighbors::k_nearest;

    /// Points on two separate sheets with a gap between them, in Morton order: the curve
    /// jumps between the sheets and across its own cells.
    fn sheets() -> Vec<Vec3> {
        let mut random = 7u64;
        let mut next = || {
            random = random.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (random >> 40) as f32 / (1u64 << 24) as f32
        };
        let points: Vec<Vec3> = (0..6000)
            .map(|i| {
                let sheet = if i % 3 == 0 { 5.0 } else { 0.0 };
                Vec3::new(next() * 4.0 + sheet, next() * 0.02, next() * 4.0)
            })
            .collect();
        morton_order(&points).into_iter().map(|i| points[i as usize]).collect()
    }

    /// The bound of every point, the whole cloud taken as the tile.
    fn every_bound(points: &[Vec3], distinct: &DistinctNeighbours) -> Vec<f32> {
        let runs = points.len().div_ceil(GATE_RUN_POINTS);
        neighbourhood_bounds(points, 0..points.len(), distinct, &vec![true; runs])
    }

    fn exact(points: &[Vec3], k: usize) -> Vec<f32> {
        let neighbors = k_nearest(points, k);
        (0..points.len()).map(|i| neighbors.distances_of(i)[k - 1]).collect()
    }

    #[test]
    fn the_bounds_never_fall_short_of_the_kth_neighbour() {
        let points = sheets();
        for k in [1, 9, 16] {
            let exact = exact(&points, k);
            let bounds = every_bound(&points, &DistinctNeighbours::new(k, 0.0));
            for (i, (bound, radius)) in bounds.iter().zip(&exact).enumerate() {
                assert!(bound >= radius, "k {k}, point {i}: bound {bound} below the radius {radius}");
            }
        }
    }

    #[test]
    fn the_bounds_stay_near_the_kth_neighbour() {
        let points = sheets();
        let exact = exact(&points, 16);
        let bounds = every_bound(&points, &DistinctNeighbours::new(16, 0.0));
        let mut ratios: Vec<f32> = bounds.iter().zip(&exact).map(|(b, r)| b / r).collect();
        ratios.sort_by(f32::total_cmp);
        let mean = ratios.iter().sum::<f32>() / ratios.len() as f32;
        let (p99, worst) = (ratios[ratios.len() * 99 / 100], ratios[ratios.len() - 1]);
        println!("bound / radius: mean {mean}, p99 {p99}, worst {worst}");
        assert!(mean < 1.5, "bounds {mean} times the radius on average");
        assert!(p99 < 2.25, "1% of the bounds over {p99} times their radius");
        assert!(worst < 3.0, "a bound {worst} times its radius");
    }

    #[test]
    fn duplicates_do_not_count_as_neighbours() {
        // Every point three times, each copy a little off (within the duplicate distance):
        // prep keeps one of each, so a point's k-th neighbour is the k-th distinct position.
        let distinct_points = sheets();
        let near = 1e-6;
        let points: Vec<Vec3> = distinct_points
            .iter()
            .flat_map(|&p| [p, p + Vec3::splat(0.4 * near), p - Vec3::new(0.3 * near, 0.0, 0.0)])
            .collect();
        let exact = exact(&distinct_points, 16);
        let bounds = every_bound(&points, &DistinctNeighbours::new(16, near));
        for (i, radius) in exact.iter().enumerate() {
            let bound = bounds[3 * i];
            assert!(bound >= *radius, "point {i}: bound {bound} below the merged radius {radius}");
        }
        assert!(bounds.iter().all(|b| b.is_finite()), "the tree finds enough distinct neighbours");
    }

    #[test]
    fn too_few_points_are_unbounded() {
        let points = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let bounds = |k| every_bound(&points, &DistinctNeighbours::new(k, 0.0));
        assert_eq!(bounds(3), vec![f32::INFINITY; 3]);
        assert!(bounds(2).iter().all(|b| b.is_finite()));
    }
}
