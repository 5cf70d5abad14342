//! Where the cameras stand around the model.

use glam::Vec3;

use crate::FidelityError;

/// Fewer views leave whole sides of a closed model unseen.
pub const MINIMUM_VIEWS: usize = 6;

/// `count` unit directions from the model's centre toward the cameras. Six gives the faces
/// of a cube (+x, -x, +y, -y, +z, -z), the views a reader can name; more are spread evenly
/// over the sphere by a Fibonacci lattice, so that no side is sampled twice as densely.
pub fn view_directions(count: usize) -> Result<Vec<Vec3>, FidelityError> {
    match count {
        c if c < MINIMUM_VIEWS => Err(FidelityError::TooFewViews { requested: c, minimum: MINIMUM_VIEWS }),
        MINIMUM_VIEWS => Ok(vec![Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z]),
        _ => Ok(fibonacci_sphere(count)),
    }
}

fn fibonacci_sphere(count: usize) -> Vec<Vec3> {
    let golden_angle = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..count)
        .map(|i| {
            // Heights at the centres of `count` equal-area bands, so both poles are left out.
            let y = 1.0 - (2.0 * i as f32 + 1.0) / count as f32;
            let ring = (1.0 - y * y).max(0.0).sqrt();
            let angle = golden_angle * i as f32;
            Vec3::new(ring * angle.cos(), y, ring * angle.sin())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_views_are_the_cube_faces_and_more_are_unit_and_distinct() {
        let six = view_directions(6).unwrap();
        assert_eq!(six.iter().copied().sum::<Vec3>(), Vec3::ZERO);
        let many = view_directions(20).unwrap();
        assert_eq!(many.len(), 20);
        assert!(many.iter().all(|d| (d.length() - 1.0).abs() < 1e-5));
        let closest = many
            .iter()
            .enumerate()
            .flat_map(|(i, a)| many[i + 1..].iter().map(move |b| a.distance(*b)))
            .fold(f32::INFINITY, f32::min);
        assert!(closest > 0.3, "views bunch up: closest pair {closest}");
    }

    #[test]
    fn fewer_than_six_views_is_an_error() {
        assert!(matches!(view_directions(5), Err(FidelityError::TooFewViews { requested: 5, .. })));
    }
}
