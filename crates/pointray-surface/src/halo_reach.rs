//! How far a tile's halo reaches: it holds each tile point's neighbourhood, so that every
//! patch of the tile that depends only on its neighbourhood (position, fit, support, colour,
//! a normal from the input or toward a sensor) is the one a single pass makes. Each point
//! reaches as far as an upper bound on its neighbourhood radius: any upper bound keeps that
//! equality, and a loose one only adds halo points. The bound comes from the points' order
//! along the Morton curve, in linear time, and from a k-d tree only where the curve jumps.
//! Both look past the tile's ends along the curve, where a few points cut off by the curve
//! have their neighbours.
//!
//! The halo does not hold its own points' neighbourhoods in turn. Those points' normals serve
//! only to orient the tile's normals over the neighbour graph, where a tile's sign may differ
//! from a single pass's anyway; reaching twice as far for them quadrupled the halo, and around
//! an isolated point, whose neighbours lie far off on a dense surface, it pulled a wide ball
//! of that surface into the halo.

use std::num::NonZeroUsize;
use std::ops::Range;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use crate::prep_settings::PrepSettings;

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

/// How far the halo reaches around each point of `curve[core]`. `curve` holds a stretch of
/// the cloud in Morton order: the tile's points (`core`) and up to `CURVE_CONTEXT` points on
/// either side of them.
pub(crate) fn halo_reaches(curve: &[Vec3], core: Range<usize>, settings: &PrepSettings) -> Vec<f32> {
    neighbourhood_bounds(curve, core, neighbourhood_size(settings))
}

/// The most neighbours any stage of prep takes.
fn neighbourhood_size(settings: &PrepSettings) -> usize {
    settings.k.max(settings.normal_k) as usize
}

/// The distance of each point of `points[core]` to its `k`-th nearest neighbour among
/// `points`, or more: an upper bound on its neighbourhood in any cloud that holds them.
/// Unbounded for fewer than `k + 1` points.
pub(crate) fn neighbourhood_bounds(points: &[Vec3], core: Range<usize>, k: usize) -> Vec<f32> {
    if points.len() <= k || k == 0 {
        return vec![f32::INFINITY; core.len()];
    }
    let mut bounds = curve_window_radii(points, core.clone(), k);
    let loose: Vec<usize> = (0..bounds.len()).into_par_iter().filter(|&i| stands_out(&bounds, i)).collect();
    let queries: Vec<usize> = loose.iter().map(|&i| core.start + i).collect();
    for (i, radius) in loose.iter().zip(exact_radii(points, &queries, k)) {
        bounds[*i] = radius;
    }
    bounds
}

/// The distance of each point of `points[core]` to its `k`-th nearest neighbour among the
/// `CURVE_WINDOW` points on either side of it: the `k`-th nearest of a subset lies no nearer
/// than the `k`-th nearest of all. Callers guarantee `points.len() > k`.
fn curve_window_radii(points: &[Vec3], core: Range<usize>, k: usize) -> Vec<f32> {
    core.into_par_iter()
        .map_init(Vec::new, |squared: &mut Vec<f32>, i| {
            let window = i.saturating_sub(CURVE_WINDOW)..(i + CURVE_WINDOW + 1).min(points.len());
            squared.clear();
            squared.extend(window.filter(|&j| j != i).map(|j| (points[j] - points[i]).length_squared()));
            if squared.len() < k {
                return f32::INFINITY;
            }
            let (_, kth, _) = squared.select_nth_unstable_by(k - 1, f32::total_cmp);
            kth.sqrt()
        })
        .collect()
}

/// Whether bound `i` is more than `LOOSE_BOUND` times the median of the bounds around it.
fn stands_out(bounds: &[f32], i: usize) -> bool {
    let span = &bounds[i.saturating_sub(MEDIAN_SPAN)..(i + MEDIAN_SPAN + 1).min(bounds.len())];
    let mut around = span.to_vec();
    let middle = around.len() / 2;
    let (_, median, _) = around.select_nth_unstable_by(middle, f32::total_cmp);
    bounds[i] > LOOSE_BOUND * *median
}

/// The `k`-th nearest neighbour's distance of each point of `points` named in `queries`.
fn exact_radii(points: &[Vec3], queries: &[usize], k: usize) -> Vec<f32> {
    if queries.is_empty() {
        return Vec::new();
    }
    let entries: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    let tree: ImmutableKdTree<f32, 3> = ImmutableKdTree::new_from_slice_parallel(&entries)
        .unwrap_or_else(|e| unreachable!("a tile's points fit u32 indices: {e}"));
    // The point itself comes back at distance 0, so the (k + 1)-th nearest is the k-th other.
    let wanted = NonZeroUsize::new(k + 1).unwrap_or(NonZeroUsize::MIN);
    queries
        .par_iter()
        .map(|&i| {
            let found = tree.query(&entries[i]).nearest_n::<SquaredEuclidean<f32>>(wanted).execute();
            found.iter().map(|hit| hit.distance).fold(0.0, f32::max).sqrt()
        })
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

    fn exact(points: &[Vec3], k: usize) -> Vec<f32> {
        let neighbors = k_nearest(points, k);
        (0..points.len()).map(|i| neighbors.distances_of(i)[k - 1]).collect()
    }

    #[test]
    fn the_bounds_never_fall_short_of_the_kth_neighbour() {
        let points = sheets();
        for k in [1, 9, 16] {
            let exact = exact(&points, k);
            let bounds = neighbourhood_bounds(&points, 0..points.len(), k);
            for (i, (bound, radius)) in bounds.iter().zip(&exact).enumerate() {
                assert!(bound >= radius, "k {k}, point {i}: bound {bound} below the radius {radius}");
            }
        }
    }

    #[test]
    fn the_bounds_stay_near_the_kth_neighbour() {
        let points = sheets();
        let exact = exact(&points, 16);
        let bounds = neighbourhood_bounds(&points, 0..points.len(), 16);
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
    fn too_few_points_are_unbounded() {
        let points = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert_eq!(neighbourhood_bounds(&points, 0..3, 3), vec![f32::INFINITY; 3]);
        assert!(neighbourhood_bounds(&points, 0..3, 2).iter().all(|b| b.is_finite()));
    }
}
