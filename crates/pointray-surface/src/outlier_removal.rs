//! Statistical outlier removal: stray returns (birds, dust, multipath) sit far
//! from the surface, and `prep` would give each one a patch as large as its distance to
//! the surface. A point goes when its mean distance to its `neighbors` nearest points is
//! more than `sigmas` standard deviations above the cloud's mean of those means.

use glam::Vec3;
use pointray_patches::OutlierFilter;
use rayon::prelude::*;

use crate::neighbors::k_nearest;

/// `true` for every point to keep. Needs more than `filter.neighbors` points (prep has
/// checked that there are more than its own `k`); with fewer, it keeps them all.
pub fn inliers(filter: &OutlierFilter, points: &[Vec3]) -> Vec<bool> {
    let k = filter.neighbors as usize;
    if points.len() <= k {
        return vec![true; points.len()];
    }
    let table = k_nearest(points, k);
    let means: Vec<f64> = (0..points.len())
        .into_par_iter()
        .map(|i| table.distances_of(i).iter().map(|&d| f64::from(d)).sum::<f64>() / k as f64)
        .collect();
    let limit = mean_plus_sigmas(&means, f64::from(filter.sigmas));
    means.par_iter().map(|&mean| mean <= limit).collect()
}

/// `mean + sigmas * standard deviation` of `values` (population deviation, as PCL).
fn mean_plus_sigmas(values: &[f64], sigmas: f64) -> f64 {
    let n = values.len() as f64;
    let mean = values.par_iter().sum::<f64>() / n;
    let variance = values.par_iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    mean + sigmas * variance.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limit_is_mean_plus_sigmas_deviations() {
        // mean 2, population deviation 1
        assert_eq!(mean_plus_sigmas(&[1.0, 3.0, 1.0, 3.0], 2.0), 4.0);
    }

    #[test]
    fn a_lone_point_far_from_a_grid_goes() {
        let mut points: Vec<Vec3> =
            (0..400).map(|i| Vec3::new((i % 20) as f32, (i / 20) as f32, 0.0)).collect();
        points.push(Vec3::new(10.0, 10.0, 50.0));
        let keep = inliers(&OutlierFilter { neighbors: 8, sigmas: 3.0 }, &points);
        assert_eq!(keep.iter().filter(|&&k| !k).count(), 1);
        assert!(!keep[400]);
    }
}
