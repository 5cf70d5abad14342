//! Duplicate merging, self-free neighbour rows, Morton order and sensor orientation.

use crate::normals_support;

use glam::Vec3;
use normals_support::NORMAL_K;
use pointray_surface::duplicates::merge_duplicates;
use pointray_surface::morton::morton_order;
use pointray_surface::neighbors::k_nearest;
use pointray_surface::normals::pca_normals;
use pointray_surface::orientation::orient_toward;

/// A 40 x 40 x 1 grid of unit spacing: distinct points, far apart from each other.
fn grid() -> Vec<Vec3> {
    (0..1600).map(|i| Vec3::new((i % 40) as f32, (i / 40) as f32, 0.1 * ((i % 7) as f32))).collect()
}

/// `grid()` followed by 50 exact copies and 30 copies moved one f32 step (each of a different
/// grid point), and 20 points moved by 0.3 (not duplicates).
fn cloud_with_duplicates() -> (Vec<Vec3>, usize) {
    let originals = grid();
    let mut points = originals.clone();
    points.extend((0..50).map(|i| originals[i * 7]));
    let step = |p: Vec3| Vec3::new(p.x, p.y.next_up(), p.z);
    points.extend((0..30).map(|i| step(originals[i * 11 + 3])));
    points.extend((0..20).map(|i| originals[i * 13 + 5] + Vec3::new(0.3, 0.0, 0.0)));
    (points, 80)
}

#[test]
fn merge_counts_exact_and_near_duplicates_and_keeps_the_first() {
    let (points, duplicates) = cloud_with_duplicates();
    let merge = merge_duplicates(&points, 1.0);
    assert_eq!(merge.merged_count, duplicates);
    assert_eq!(merge.kept.len(), points.len() - duplicates);
    assert!(merge.kept.windows(2).all(|w| w[0] < w[1]), "input order preserved");
    let expected: Vec<u32> = (0..1600).chain(1680..1700).collect();
    assert_eq!(merge.kept, expected, "the originals are kept, the copies dropped");
}

#[test]
fn zero_tolerance_merges_exact_duplicates_only() {
    let (points, _) = cloud_with_duplicates();
    assert_eq!(merge_duplicates(&points, 0.0).merged_count, 50);
}

#[test]
fn all_identical_points_merge_to_one() {
    let points = vec![Vec3::new(1.0, 2.0, 3.0); 10_000];
    let merge = merge_duplicates(&points, 1.0);
    assert_eq!(merge.kept, vec![0]);
    assert_eq!(merge.merged_count, 9_999);
}

#[test]
fn neighbours_exclude_self_and_normals_stay_finite_with_duplicates() {
    let (mut points, _) = cloud_with_duplicates();
    // A cluster larger than k + 1 of one position: ties at distance 0 everywhere.
    let clustered = points[100];
    points.extend(std::iter::repeat_n(clustered, NORMAL_K + 5));
    let neighbors = k_nearest(&points, NORMAL_K);
    assert_eq!(neighbors.point_count(), points.len());
    for i in 0..points.len() {
        let row = neighbors.of(i);
        assert!(!row.contains(&(i as u32)), "point {i} is its own neighbour: {row:?}");
        let distances = neighbors.distances_of(i);
        assert!(distances.windows(2).all(|w| w[0] <= w[1]), "row {i} not sorted: {distances:?}");
        for (&j, &d) in row.iter().zip(distances) {
            assert!((points[i].distance(points[j as usize]) - d).abs() < 1e-5);
        }
    }
    let normals = pca_normals(&points, &neighbors, NORMAL_K);
    assert!(normals.iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-4));
}

#[test]
fn neighbours_are_the_true_nearest() {
    let points = grid();
    let neighbors = k_nearest(&points, 8);
    for i in (0..points.len()).step_by(37) {
        let mut brute: Vec<f32> =
            (0..points.len()).filter(|&j| j != i).map(|j| points[i].distance(points[j])).collect();
        brute.sort_by(f32::total_cmp);
        for (found, expected) in neighbors.distances_of(i).iter().zip(&brute) {
            assert!((found - expected).abs() < 1e-5, "point {i}: {found} vs {expected}");
        }
    }
}

#[test]
fn morton_order_is_a_local_permutation_independent_of_input_order() {
    // The grid in a pseudo-random order.
    let mut scrambled: Vec<usize> = (0..1600).collect();
    scrambled.sort_by_key(|&i| (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(29));
    let shuffled: Vec<Vec3> = scrambled.iter().map(|&i| grid()[i]).collect();
    let mut order = morton_order(&shuffled);
    let sorted: Vec<Vec3> = order.iter().map(|&i| shuffled[i as usize]).collect();
    let path_length = |points: &[Vec3]| -> f32 { points.windows(2).map(|w| w[0].distance(w[1])).sum() };
    let (sorted_length, shuffled_length) = (path_length(&sorted), path_length(&shuffled));
    assert!(sorted_length < 0.15 * shuffled_length, "{sorted_length} vs {shuffled_length}");
    assert_eq!(sorted[0], Vec3::ZERO, "starts at the minimum corner");
    let from_grid: Vec<Vec3> = morton_order(&grid()).iter().map(|&i| grid()[i as usize]).collect();
    assert_eq!(sorted, from_grid, "the curve, not the input, decides the order");
    order.sort_unstable();
    assert_eq!(order, (0..1600).collect::<Vec<_>>(), "a permutation");
}

#[test]
fn orient_toward_faces_every_normal_to_the_sensor() {
    let points = grid();
    let sensor = Vec3::new(20.0, 20.0, 50.0);
    let mut normals: Vec<Vec3> = (0..points.len())
        .map(|i| if i % 3 == 0 { Vec3::Z } else { Vec3::new(0.2, -0.1, -1.0).normalize() })
        .collect();
    orient_toward(&points, &mut normals, sensor);
    assert!(points.iter().zip(&normals).all(|(&p, n)| n.dot(sensor - p) > 0.0));
}
