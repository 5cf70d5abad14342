//! A re-simulated sweep against the real one, scored the way LiDAR simulation research scores
//! novel views: the share of rays whose range agrees, the median range error, and the
//! Chamfer distance between the two point sets.

use glam::DVec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use pointray_io::median;
use rayon::prelude::*;
use serde::Serialize;

use crate::resimulation::SweepRays;

/// A ray agrees when its re-simulated range lies within the larger of these of the measured one.
pub const ABSOLUTE_TOLERANCE: f64 = 0.1;
pub const RANGE_TOLERANCE: f64 = 0.01;

/// The Chamfer distance counts returns within this range of the sensor (metres).
pub const CHAMFER_RANGE: f64 = 50.0;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RangeAgreement {
    pub rays: usize,
    /// Rays whose range agrees within max(`ABSOLUTE_TOLERANCE`, `RANGE_TOLERANCE` x range).
    pub agreeing: usize,
    pub agreeing_fraction: f64,
    /// The median of |re-simulated - measured| over rays that met a surface.
    pub median_abs_range_error: Option<f64>,
    /// Rays that met a surface well before the measured return.
    pub floaters: usize,
    /// Rays that met a surface well beyond the measured return.
    pub beyond: usize,
    /// Rays that met nothing.
    pub misses: usize,
    /// The mean distance from each point of one set to the nearest of the other (returns
    /// within `CHAMFER_RANGE`), each way, and their mean: the symmetric Chamfer distance.
    pub chamfer_simulated_to_real: Option<f64>,
    pub chamfer_real_to_simulated: Option<f64>,
    pub chamfer: Option<f64>,
}

impl RangeAgreement {
    /// Scores `simulated` (one range or none per ray of `rays`) against the ranges measured.
    pub fn of(rays: &SweepRays, simulated: &[Option<f64>]) -> Self {
        let mut errors = Vec::new();
        let (mut agreeing, mut floaters, mut beyond, mut misses) = (0, 0, 0, 0);
        for (&measured, &range) in rays.ranges.iter().zip(simulated) {
            let Some(range) = range else {
                misses += 1;
                continue;
            };
            errors.push((range - measured).abs());
            let tolerance = ABSOLUTE_TOLERANCE.max(RANGE_TOLERANCE * measured);
            match range - measured {
                error if error.abs() <= tolerance => agreeing += 1,
                error if error < 0.0 => floaters += 1,
                _ => beyond += 1,
            }
        }
        let real = within_chamfer_range(rays, rays.ranges.iter().copied().map(Some));
        let simulated_points = within_chamfer_range(rays, simulated.iter().copied());
        let to_real = mean_nearest_distance(&simulated_points, &real);
        let to_simulated = mean_nearest_distance(&real, &simulated_points);
        let rays_cast = rays.ranges.len();
        Self {
            rays: rays_cast,
            agreeing,
            agreeing_fraction: agreeing as f64 / rays_cast.max(1) as f64,
            median_abs_range_error: median(errors),
            floaters,
            beyond,
            misses,
            chamfer_simulated_to_real: to_real,
            chamfer_real_to_simulated: to_simulated,
            chamfer: to_real.zip(to_simulated).map(|(a, b)| (a + b) / 2.0),
        }
    }
}

/// The points along `rays` at `ranges` (one or none per ray) within `CHAMFER_RANGE`.
fn within_chamfer_range(rays: &SweepRays, ranges: impl Iterator<Item = Option<f64>>) -> Vec<DVec3> {
    ranges
        .enumerate()
        .filter_map(|(i, range)| range.filter(|&r| r <= CHAMFER_RANGE).map(|r| rays.point(i, r)))
        .collect()
}

/// The mean distance from each of `from` to the nearest of `to`; `None` when either is empty.
fn mean_nearest_distance(from: &[DVec3], to: &[DVec3]) -> Option<f64> {
    if from.is_empty() || to.is_empty() {
        return None;
    }
    let entries: Vec<[f64; 3]> = to.iter().map(|p| p.to_array()).collect();
    let tree: ImmutableKdTree<f64, 3> = ImmutableKdTree::new_from_slice_parallel(&entries).ok()?;
    let nearest = |p: &DVec3| tree.query(&p.to_array()).nearest_one::<SquaredEuclidean<f64>>().execute();
    let total: f64 = from.par_iter().map(|p| nearest(p).distance.sqrt()).sum();
    Some(total / from.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rays() -> SweepRays {
        SweepRays {
            origins: vec![DVec3::ZERO; 4],
            directions: vec![DVec3::X, DVec3::Y, DVec3::Z, -DVec3::X],
            ranges: vec![10.0, 20.0, 30.0, 40.0],
        }
    }

    #[test]
    fn rays_split_into_agreeing_floaters_beyond_and_misses() {
        let scored = RangeAgreement::of(&rays(), &[Some(10.05), Some(15.0), Some(31.0), None]);
        assert_eq!((scored.agreeing, scored.floaters, scored.beyond, scored.misses), (1, 1, 1, 1));
        assert_eq!(scored.median_abs_range_error, Some(1.0));
    }

    #[test]
    fn the_same_ranges_give_a_chamfer_of_zero() {
        let measured: Vec<Option<f64>> = rays().ranges.iter().copied().map(Some).collect();
        let scored = RangeAgreement::of(&rays(), &measured);
        assert_eq!(scored.agreeing, 4);
        assert_eq!(scored.chamfer, Some(0.0));
    }
}
