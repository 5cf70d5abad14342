//! PCA normals (METHOD.md §2.2): the direction of least spread of each neighbourhood.

use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;

use crate::neighbors::Neighbors;

/// Unoriented unit normals: for each point, the eigenvector of the smallest eigenvalue of
/// the covariance of the point and its first `normal_k` neighbours (at most `neighbors.k`).
/// Degenerate neighbourhoods (coincident or collinear points) still give a finite unit
/// vector, just an arbitrary one among the equally good directions.
pub fn pca_normals(points: &[Vec3], neighbors: &Neighbors, normal_k: usize) -> Vec<Vec3> {
    let used = normal_k.min(neighbors.k);
    (0..points.len())
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let covariance = neighbourhood_covariance(points, i, &neighbors.of(i)[..used]);
            smallest_eigenvector(covariance).as_vec3()
        })
        .collect()
}

/// Covariance of `p_i` and its neighbours in one pass, `E[d dᵀ] - E[d] E[d]ᵀ` over the
/// offsets `d = p_j - p_i`: in f64 and relative to `p_i`, so that the subtraction loses
/// nothing even for recentred-but-large coordinates.
pub(crate) fn neighbourhood_covariance(points: &[Vec3], i: usize, neighbours: &[u32]) -> DMat3 {
    let origin = points[i];
    let mut sum = DVec3::ZERO;
    let mut products = [0.0f64; 6]; // xx, xy, xz, yy, yz, zz
    for &j in neighbours {
        let d = (points[j as usize] - origin).as_dvec3();
        sum += d;
        products[0] += d.x * d.x;
        products[1] += d.x * d.y;
        products[2] += d.x * d.z;
        products[3] += d.y * d.y;
        products[4] += d.y * d.z;
        products[5] += d.z * d.z;
    }
    let count = (neighbours.len() + 1) as f64; // p_i itself adds a zero offset
    let mean = sum / count;
    let [xx, xy, xz, yy, yz, zz] = products.map(|p| p / count);
    DMat3::from_cols(
        DVec3::new(xx - mean.x * mean.x, xy - mean.x * mean.y, xz - mean.x * mean.z),
        DVec3::new(xy - mean.x * mean.y, yy - mean.y * mean.y, yz - mean.y * mean.z),
        DVec3::new(xz - mean.x * mean.z, yz - mean.y * mean.z, zz - mean.z * mean.z),
    )
}

/// The unit eigenvector of the smallest eigenvalue of a symmetric matrix. The closed form
/// serves where that eigenvalue stands apart from the others; nearly equal eigenvalues
/// (collinear or coincident points) go to Jacobi rotations, which stay accurate there.
pub(crate) fn smallest_eigenvector(matrix: DMat3) -> DVec3 {
    closed_form_smallest_eigenvector(matrix).unwrap_or_else(|| jacobi_smallest_eigenvector(matrix))
}

/// Below this ratio of the gap between the two smallest eigenvalues to the spread of all
/// three, the closed form's eigenvector is left to Jacobi: its error grows as the inverse of
/// that ratio (times f64 precision), while Jacobi's does not.
const CLOSED_FORM_MIN_GAP: f64 = 1e-4;

/// The smallest root of the characteristic cubic in trigonometric form, and its eigenvector
/// as the longest cross product of two rows of `A - λI`, which span the plane orthogonal to
/// it.
fn closed_form_smallest_eigenvector(matrix: DMat3) -> Option<DVec3> {
    let scale = matrix.abs().to_cols_array().into_iter().fold(0.0, f64::max);
    if !scale.is_normal() {
        return None;
    }
    let a = matrix * scale.recip();
    let mean = (a.x_axis.x + a.y_axis.y + a.z_axis.z) / 3.0;
    let centred = a - DMat3::from_diagonal(DVec3::splat(mean));
    let spread = (centred.to_cols_array().iter().map(|e| e * e).sum::<f64>() / 6.0).sqrt();
    if spread <= f64::EPSILON {
        return None;
    }
    let half_determinant = (centred * spread.recip()).determinant() / 2.0;
    let angle = half_determinant.clamp(-1.0, 1.0).acos() / 3.0;
    let smallest = mean + 2.0 * spread * (angle + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let rows = a - DMat3::from_diagonal(DVec3::splat(smallest));
    let (r0, r1, r2) = (rows.x_axis, rows.y_axis, rows.z_axis);
    let longest = [r0.cross(r1), r0.cross(r2), r1.cross(r2)]
        .into_iter()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?;
    let row_spread = r0.length_squared() + r1.length_squared() + r2.length_squared();
    (longest.length() > CLOSED_FORM_MIN_GAP * row_spread).then(|| longest.normalize())
}

/// Sweeps of the cyclic Jacobi method: it converges quadratically, so 3x3 matrices are
/// diagonal to f64 precision after 4 or 5; the cap only guards against NaN input.
const MAX_JACOBI_SWEEPS: usize = 16;

/// The same eigenvector by cyclic Jacobi rotations.
fn jacobi_smallest_eigenvector(matrix: DMat3) -> DVec3 {
    let mut a = matrix.to_cols_array_2d();
    let mut v = DMat3::IDENTITY.to_cols_array_2d();
    for _ in 0..MAX_JACOBI_SWEEPS {
        let off_diagonal = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diagonal = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off_diagonal <= f64::EPSILON * diagonal || !off_diagonal.is_normal() {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            jacobi_rotate(&mut a, &mut v, p, q);
        }
    }
    let smallest = (0..3).min_by(|&x, &y| a[x][x].total_cmp(&a[y][y])).unwrap_or(2);
    let normal = DVec3::from_array(v[smallest]);
    normal.try_normalize().unwrap_or(DVec3::Z)
}

/// One Jacobi rotation that zeroes `a[p][q]` (Numerical Recipes' stable form);
/// the rotation is accumulated into the columns of `v`.
fn jacobi_rotate(a: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize) {
    let apq = a[p][q];
    if apq == 0.0 {
        return;
    }
    let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    let mut rotated = *a;
    for r in 0..3 {
        rotated[r][p] = c * a[r][p] - s * a[r][q];
        rotated[r][q] = s * a[r][p] + c * a[r][q];
    }
    let columns_rotated = rotated;
    for r in 0..3 {
        rotated[p][r] = c * columns_rotated[p][r] - s * columns_rotated[q][r];
        rotated[q][r] = s * columns_rotated[p][r] + c * columns_rotated[q][r];
    }
    *a = rotated;
    let (vp, vq) = (v[p], v[q]);
    for r in 0..3 {
        v[p][r] = c * vp[r] - s * vq[r];
        v[q][r] = s * vp[r] + c * vq[r];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smallest_eigenvector_of_a_rotated_diagonal_matrix() {
        let rotation = DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7);
        let matrix = rotation * DMat3::from_diagonal(DVec3::new(5.0, 1e-9, 2.0)) * rotation.transpose();
        let expected = rotation.col(1);
        let found = smallest_eigenvector(matrix);
        assert!(found.dot(expected).abs() > 1.0 - 1e-12, "{found} vs {expected}");
    }

    /// Covariances of points scattered with the given spreads along three random axes.
    fn covariances(spreads: DVec3) -> impl Iterator<Item = DMat3> {
        (0..200).map(move |i| {
            let angles = (i as f64 * 0.37, i as f64 * -1.13 + 0.2, i as f64 * 0.71 - 0.5);
            let rotation = DMat3::from_euler(glam::EulerRot::XYZ, angles.0, angles.1, angles.2);
            rotation * DMat3::from_diagonal(spreads * spreads) * rotation.transpose()
        })
    }

    #[test]
    fn the_closed_form_agrees_with_the_rotations_where_it_serves() {
        for spreads in [DVec3::new(1.0, 0.7, 0.0), DVec3::new(3.0, 1.0, 0.01), DVec3::new(1.0, 1.0, 0.5)] {
            for matrix in covariances(spreads) {
                let closed = closed_form_smallest_eigenvector(matrix).expect("a clear smallest eigenvalue");
                let rotated = jacobi_smallest_eigenvector(matrix);
                assert!(closed.dot(rotated).abs() > 1.0 - 1e-12, "{closed} vs {rotated} for {spreads}");
            }
        }
    }

    #[test]
    fn nearly_equal_smallest_eigenvalues_go_to_the_rotations() {
        for spreads in [DVec3::new(1.0, 0.0, 0.0), DVec3::new(1.0, 1e-7, 0.0), DVec3::ONE] {
            for matrix in covariances(spreads) {
                assert_eq!(closed_form_smallest_eigenvector(matrix), None, "{spreads}");
                let found = smallest_eigenvector(matrix);
                assert!((found.length() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn smallest_eigenvector_of_zero_matrix_is_finite_and_unit() {
        let found = smallest_eigenvector(DMat3::ZERO);
        assert!((found.length() - 1.0).abs() < 1e-12);
    }
}
