//! How far apart the returns lie around a few of them.

use std::num::NonZeroUsize;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use crate::FidelityError;

/// For each of `queries` (indices into `points`), the distance to its `neighbor`th nearest
/// other point; the farthest found when there are fewer.
pub fn nth_neighbor_distances(
    points: &[Vec3],
    queries: &[usize],
    neighbor: usize,
) -> Result<Vec<f32>, FidelityError> {
    let entries: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    let tree = ImmutableKdTree::<f32, 3>::new_from_slice_parallel(&entries)
        .map_err(|_| FidelityError::TooManyPoints(points.len()))?;
    let wanted = NonZeroUsize::new(neighbor + 1).unwrap_or(NonZeroUsize::MIN);
    Ok(queries
        .par_iter()
        .map(|&i| {
            let found = tree.query(&entries[i]).nearest_n::<SquaredEuclidean<f32>>(wanted).execute();
            let others = found.iter().filter(|hit| hit.item as usize != i).take(neighbor);
            others.last().map_or(0.0, |hit| hit.distance.sqrt())
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nth_neighbour_on_a_line_of_unit_steps() {
        let line: Vec<Vec3> = (0..10).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
        // From point 5, the 4th nearest others are at distance 2; from the end, at 4.
        assert_eq!(nth_neighbor_distances(&line, &[5, 0], 4).unwrap(), vec![2.0, 4.0]);
        let pair = [Vec3::ZERO, Vec3::X];
        assert_eq!(nth_neighbor_distances(&pair, &[0], 4).unwrap(), vec![1.0]);
    }
}
