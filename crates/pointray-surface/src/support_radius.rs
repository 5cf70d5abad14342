//! The support radius `d_i` of a patch (METHOD.md §2.3).

use glam::Vec3;

/// How `d_i` was obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusSource {
    /// The tangential length of `v`, as METHOD.md §2.3 defines it.
    Tangential,
    /// `|v|`: the farthest neighbour lies (almost) along the normal.
    Distance,
    /// A fraction of the mean neighbour spacing: `v` itself was (almost) zero.
    Spacing,
}

/// Below this fraction of `|v|`, the tangential length is judged to be zero.
const NEGLIGIBLE_TANGENTIAL: f32 = 1e-4;

/// `d_i = |v - (v·n) n|` for `v = farthest - point`; never zero. `mean_spacing` is the
/// cloud's mean neighbour spacing, used when `v` itself vanishes.
pub fn support_radius(point: Vec3, normal: Vec3, farthest: Vec3, mean_spacing: f32) -> (f32, RadiusSource) {
    let v = farthest - point;
    let distance = v.length();
    let tangential = (v - v.dot(normal) * normal).length();
    if tangential > NEGLIGIBLE_TANGENTIAL * distance && tangential > 0.0 {
        (tangential, RadiusSource::Tangential)
    } else if distance > 0.0 {
        (distance, RadiusSource::Distance)
    } else {
        (0.5 * mean_spacing.max(f32::MIN_POSITIVE), RadiusSource::Spacing)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangential_length_of_the_farthest_offset() {
        let (d, source) = support_radius(Vec3::ZERO, Vec3::Z, Vec3::new(3.0, 4.0, 7.0), 1.0);
        assert_eq!((d, source), (5.0, RadiusSource::Tangential));
    }

    #[test]
    fn never_zero() {
        let along_normal = support_radius(Vec3::ZERO, Vec3::Z, Vec3::new(0.0, 0.0, 2.0), 1.0);
        assert_eq!(along_normal, (2.0, RadiusSource::Distance));
        let coincident = support_radius(Vec3::ONE, Vec3::Z, Vec3::ONE, 0.4);
        assert_eq!(coincident, (0.2, RadiusSource::Spacing));
        assert!(support_radius(Vec3::ONE, Vec3::Z, Vec3::ONE, 0.0).0 > 0.0);
    }
}
